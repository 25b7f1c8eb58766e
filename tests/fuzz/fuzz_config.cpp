// libFuzzer target for the YAML configuration files, each through its real
// Load function: the first byte ('0' to '4') picks platform, world, perception,
// hardware or mission; the rest is written as a file beside the shipped configs (so
// that the paths it names resolve as in data/config). Built and run by
// scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>

#include "app/runtime/mission_config.h"
#include "core/config.h"
#include "core/platform.h"
#include "detection/perception_config.h"
#include "hardware/hardware_config.h"
#include "hardware/rgbd_camera.h"
#include "hardware/sim/world_config.h"
#include "tests/fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace aerograsp;
  if (size == 0) return 0;
  const std::string path =
      fuzz::WriteFile(fuzz::ScratchData() / "config" / "fuzz.yaml", data + 1, size - 1);
  try {
    switch (static_cast<std::uint8_t>(data[0] - '0') % 5) {
      case 0:
        (void)PlatformConfig::Load(path);
        break;
      case 1:
        (void)WorldConfig::Load(path);
        break;
      case 2:
        (void)LoadPerceptionOptions(path);
        break;
      case 3:
        (void)HardwareConfig::Load(path);
        break;
      default:
        (void)MissionConfig::Load(path);
        break;
    }
  } catch (const ConfigError&) {
  } catch (const HardwareError&) {
  }
  return 0;
}
