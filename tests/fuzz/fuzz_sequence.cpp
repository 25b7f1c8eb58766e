// libFuzzer target for recorded sequences through ReplayCamera: sequence.yaml
// and the CSVs (groundtruth, stamps, vehicle, joints), then every frame read.
// The input holds the files' texts one after another, separated by NUL bytes,
// in that order (a file missing from the input is absent from the folder).
// The folder holds two 4 x 3 frames' images. Built and run by scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/config.h"
#include "hardware/sequence.h"
#include "tests/fuzz/fuzz_files.h"

namespace {

namespace fs = std::filesystem;

/// A sequence folder with two 4 x 3 frames written by SequenceWriter.
const fs::path& Folder() {
  static const fs::path folder = [] {
    const fs::path dir = aerograsp::fuzz::ScratchData() / "sequence";
    aerograsp::SequenceInfo info;
    info.intrinsics.width = 4;
    info.intrinsics.height = 3;
    info.intrinsics.fx = info.intrinsics.fy = 4.0;
    info.intrinsics.cx = 2.0;
    info.intrinsics.cy = 1.5;
    aerograsp::SequenceWriter writer(dir.string(), info);
    for (int i = 0; i < 2; ++i) {
      aerograsp::RgbdFrame frame;
      frame.stamp_s = 0.1 * i;
      frame.color = aerograsp::ColorImage(4, 3);
      frame.depth = aerograsp::DepthImage(4, 3);
      writer.Write(frame);
    }
    writer.Close();
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace aerograsp;
  static const char* const kFiles[] = {"sequence.yaml", "groundtruth.csv", "stamps.csv",
                                       "vehicle.csv", "joints.csv"};
  const fs::path& folder = Folder();
  std::size_t begin = 0;
  for (const char* name : kFiles) {
    const fs::path path = folder / name;
    if (begin > size) {
      fs::remove(path);
      continue;
    }
    std::size_t end = begin;
    while (end < size && data[end] != 0) ++end;
    fuzz::WriteFile(path, data + begin, end - begin);
    begin = end + 1;
  }
  try {
    ReplayCamera camera(folder.string());
    RgbdFrame frame;
    for (int i = 0; i < 3 && camera.Grab(&frame); ++i) {
    }
  } catch (const HardwareError&) {
  } catch (const ConfigError&) {
  }
  return 0;
}
