#include "app/report/summary_file.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace aerograsp {

std::string WriteSummaryFile(const std::string& out_dir, const std::string& json_text) {
  std::filesystem::create_directories(out_dir);
  const std::string path = (std::filesystem::path(out_dir) / "summary.json").string();
  std::ofstream file(path);
  file << json_text << "\n";
  if (!file) throw std::runtime_error(path + ": cannot be written");
  return path;
}

}  // namespace aerograsp
