// Shared by the file-parser fuzz targets: a scratch copy of data/ (symbolic
// links to the shipped robots, camera, objects and configs) in which a fuzz
// input is written as a file, so that each parser is driven through its real
// Load function and the paths a config names resolve as they do in data/config.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace aerograsp::fuzz {

/// The scratch folder (made once per process): ROOT/{robots,camera,objects} link
/// to data/'s, ROOT/config holds links to every shipped config.
inline const std::filesystem::path& ScratchData() {
  static const std::filesystem::path root = [] {
    namespace fs = std::filesystem;
    std::string pattern = (fs::temp_directory_path() / "aerograsp_fuzz_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) std::abort();
    const fs::path dir(pattern);
    const fs::path data(AEROGRASP_FUZZ_DATA_DIR);
    for (const auto& entry : fs::directory_iterator(data)) {
      if (entry.path().filename() != "config")
        fs::create_directory_symlink(entry.path(), dir / entry.path().filename());
    }
    fs::create_directory(dir / "config");
    for (const auto& entry : fs::directory_iterator(data / "config"))
      fs::create_symlink(entry.path(), dir / "config" / entry.path().filename());
    std::atexit([] { std::filesystem::remove_all(ScratchData()); });
    return dir;
  }();
  return root;
}

/// Writes `size` bytes to `path` (replacing it) and returns the path as a string.
inline std::string WriteFile(const std::filesystem::path& path, const std::uint8_t* data,
                             std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

}  // namespace aerograsp::fuzz
