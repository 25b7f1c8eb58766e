// libFuzzer target for the calibration files: the first byte ('0' or '1')
// picks a calibration_<arm>.yaml (ArmCalibration::Load) or a samples.yaml read
// by `calibrate --resolve` (which loads the platform it names, computes each
// sample's forward kinematics and, given three usable samples, solves); the
// rest is the file, written beside the shipped configs. Built and run by
// scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app/calibration/calibrate_command.h"
#include "app/calibration/calibration_file.h"
#include "core/config.h"
#include "tests/fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace aerograsp;
  if (size == 0) return 0;
  const bool samples = static_cast<std::uint8_t>(data[0] - '0') % 2 == 1;
  const std::string path = fuzz::WriteFile(
      fuzz::ScratchData() / "config" / (samples ? "samples.yaml" : "calibration_left.yaml"),
      data + 1, size - 1);
  try {
    if (!samples) {
      (void)ArmCalibration::Load(path);
      return 0;
    }
    CalibrateCommandOptions options;
    options.resolve_dir = (fuzz::ScratchData() / "config").string();
    std::ostringstream out, progress;
    RunCalibrateCommand(options, out, progress);
  } catch (const ConfigError&) {
  } catch (const std::runtime_error&) {
    // The solve's own failures (too few samples, a singular pose set) are results.
  }
  return 0;
}
