#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/calibrate_command.h"
#include "core/data_dir.h"
#include "tests/common/output_folder_test.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class CalibrateCommandTest : public testing::OutputFolderTest {
 protected:
  CalibrateCommandTest() : OutputFolderTest("aerograsp_calibrate_") {}
};

TEST_F(CalibrateCommandTest, SimulatedCalibrationIsWithinAMillimetreAndBeatsOpenCv) {
  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = folder_;
  // 14 poses: from the camera's place behind the arms (data/robots/vehicle.urdf)
  // the board is seen from farther than from the old front mount, and 12 poses
  // left the rotation at 0.101 deg.
  options.poses = 14;
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("planned 14 poses of the left arm"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "calibration_left.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "poses.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples" / "000.png"));
  const nlohmann::json s = Summary();
  EXPECT_GE(s["samples_used"].get<int>(), 6);
  EXPECT_EQ(s["samples_used"].get<int>() + s["samples_rejected"].get<int>(), 14);
  EXPECT_LT(s["error_to_truth_mm"].get<double>(), 1.0);
  EXPECT_LT(s["error_to_truth_deg"].get<double>(), 0.1);
  for (const auto& [name, method] : s["opencv"].items()) {
    ASSERT_TRUE(method["ok"].get<bool>()) << name;
    EXPECT_LT(s["error_to_truth_mm"].get<double>(), method["error_to_truth_mm"].get<double>())
        << name;
  }

  // Solving again from the saved samples gives the same residuals (no truth offline).
  const double residual_mm = s["residual_mm"].get<double>();
  CalibrateCommandOptions again;
  again.resolve_dir = folder_;
  std::ostringstream out2;
  RunCalibrateCommand(again, out2, progress);
  const nlohmann::json s2 = Summary();
  EXPECT_NEAR(s2["residual_mm"].get<double>(), residual_mm, 1e-6);
  EXPECT_FALSE(s2.contains("error_to_truth_mm"));
}

// The SCS driver on the simulated bus (a pty) and the PX4 client against the
// simulated PX4 (UDP): the same poses, the same board, the same solve.
TEST_F(CalibrateCommandTest, TheRealDriversAgainstSimulatedDevicesCalibrateAsWell) {
  CalibrateCommandOptions options;
  options.arm = "right";
  options.out_dir = folder_;
  options.poses = 14;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("devices: " + DataPath("config/hardware_sim.yaml")));
  const nlohmann::json s = Summary();
  EXPECT_GE(s["samples_used"].get<int>(), 6);
  // Through the bus the joints are read on the servos' own 10-bit grid, which
  // the simulated arm's does not share: up to half a count (0.0019 rad) off, where
  // the in-process reading of a settled arm is exact. Measured: 1.28 mm /
  // 0.089 deg (right), 0.78 mm / 0.094 deg (left), against 0.49 / 0.030 and
  // 0.46 / 0.060 in process; hence 2 mm and 0.15 deg.
  EXPECT_LT(s["error_to_truth_mm"].get<double>(), 2.0);
  EXPECT_LT(s["error_to_truth_deg"].get<double>(), 0.15);
}

TEST_F(CalibrateCommandTest, AHardwareConfigWithRealArmsIsRefusedWithTheReason) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "hw.yaml").string();
  std::ofstream(path)
      << "platform: " << DataPath("config/platform_4dof.yaml")
      << "\nworld: " << DataPath("config/world_default.yaml")
      << "\narms: {backend: scs}\nautopilot: {backend: sim}\ncamera: {backend: sim}\n";
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.hardware_path = path;
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("hw.yaml: arms.backend: 'scs' drives the real arms"));
  }
}

TEST_F(CalibrateCommandTest, AllSamplesRejectedSaysSoAndKeepsThem) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.poses = 4;
  options.settle_timeout_s = 0.01;  // the arm never settles in time: every sample rejected
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("only 0 usable samples"));
  }
  EXPECT_THAT(out.str(), HasSubstr("rejected: arm not settled"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples" / "003.png"));
}

TEST_F(CalibrateCommandTest, CorruptSamplesFileNamesTheField) {
  fs::create_directories(folder_);
  std::ofstream(fs::path(folder_) / "samples.yaml") << "platform: /nonexistent.yaml\narm: left\n";
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("samples.yaml: platform"));
  }
}

}  // namespace
}  // namespace aerograsp
