// libFuzzer target for the RealSense .bag reader (ROS 1 bag through
// rosbag_storage, then the layout librealsense writes): the input is written
// as a .bag file, opened with RealsenseBagCamera and every frame grabbed (at
// most a few). Built and run by scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>

#include "hardware/bag/realsense_bag.h"
#include "tests/fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      aerograsp::fuzz::WriteFile(aerograsp::fuzz::ScratchData() / "recording.bag", data, size);
  try {
    aerograsp::RealsenseBagCamera camera(path);
    aerograsp::RgbdFrame frame;
    for (int i = 0; i < 8 && camera.Grab(&frame); ++i) {
    }
  } catch (const aerograsp::HardwareError&) {
  }
  return 0;
}
