// The calibration wizard with ROS 2 on, stopped by the independent Fast DDS
// peer (tests/peers/ros2/ros2_peer estop) as by Ctrl-C: both arms stop where
// they are and the run ends with the reason. In the built-in simulator,
// loopback only, domain 88.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/calibration/calibrate_command.h"
#include "hardware/rgbd_camera.h"

extern char** environ;

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(Ros2CalibrateTest, StopFromThePeerStopsTheWizardWithBothArmsHeld) {
  const fs::path dir =
      fs::temp_directory_path() / ("aerograsp_ros2_calibrate_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string telemetry = (dir / "telemetry.yaml").string();
  // The wizard starts once the peer's emergency-stop writer is there (the peer
  // then sends at once), so the stop arrives while it plans, before a move.
  std::ofstream(telemetry) << "mcap:\n  enabled: false\nros2:\n  emergency_stop_wait_s: 30\n"
                           << "  dds_config: " << AEROGRASP_DATA_DIR
                           << "/dds/cyclonedds_loopback.xml\n";

  // The peer sends `true` as soon as the wizard's reader is matched, and again
  // every 50 ms for 10 s (a stop written before the reader has discovered the
  // writer is dropped), as a stop button repeats its state.
  const std::vector<std::string> argv = {AEROGRASP_ROS2_PEER, "estop",   "88",
                                         "aerograsp",         "--count", "200"};
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t peer = -1;
  ASSERT_EQ(posix_spawn(&peer, args[0], nullptr, nullptr, args.data(), environ), 0);

  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = (dir / "out").string();
  options.poses = 60;  // far more time than the stop needs to arrive
  options.telemetry.config_path = telemetry;
  options.telemetry.ros2_domain = 88;
  std::istringstream no_answer;
  std::ostringstream out, progress;
  std::string error = "no error";
  try {
    RunCalibrateCommand(options, no_answer, out, progress);
  } catch (const HardwareError& e) {
    error = e.what();
  }
  int status = 0;
  waitpid(peer, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_THAT(error, HasSubstr("emergency stop from ROS 2 /aerograsp/emergency_stop (writer "));
  EXPECT_THAT(error, HasSubstr("the arms were stopped"));
  EXPECT_THAT(out.str(), HasSubstr("stopped: emergency stop from ROS 2"));
  EXPECT_THAT(out.str(), HasSubstr("both arms hold where they are"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace aerograsp
