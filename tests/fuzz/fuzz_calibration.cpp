// libFuzzer target for the calibration files: the first byte ('0' or '1') picks a
// calibration_<arm>.yaml (ArmCalibration::Load) or a samples.yaml
// (ReadCalibrationSamples, which loads the platform it names and computes each
// sample's forward kinematics); the rest is the file, written beside the
// shipped configs. Built and run by scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>

#include "app/calibration_file.h"
#include "app/calibration_samples.h"
#include "core/config.h"
#include "tests/fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace aerograsp;
  if (size == 0) return 0;
  const std::string path =
      fuzz::WriteFile(fuzz::ScratchData() / "config" / "fuzz.yaml", data + 1, size - 1);
  try {
    if (static_cast<std::uint8_t>(data[0] - '0') % 2 == 0) {
      (void)ArmCalibration::Load(path);
    } else {
      std::string platform_path;
      Side side;
      TagBoardConfig board;
      (void)ReadCalibrationSamples(path, &platform_path, &side, &board);
    }
  } catch (const ConfigError&) {
  }
  return 0;
}
