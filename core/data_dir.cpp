#include "core/data_dir.h"

#include <cstdlib>
#include <filesystem>

namespace aerograsp {

std::string DataDir() {
  if (const char* env = std::getenv("AEROGRASP_DATA_DIR"); env && *env) return env;
  return AEROGRASP_DATA_DIR;
}

std::string DataPath(const std::string& relative) {
  return (std::filesystem::path(DataDir()) / relative).string();
}

}  // namespace aerograsp
