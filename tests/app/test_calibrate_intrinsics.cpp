#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/calibration/calibrate_command.h"
#include "app/calibration/calibrate_intrinsics.h"
#include "core/camera_model.h"
#include "core/data_dir.h"
#include "core/transforms.h"
#include "hardware/rgbd_camera.h"
#include "hardware/sim/world.h"
#include "tests/common/output_folder_test.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class CalibrateIntrinsicsTest : public testing::OutputFolderTest {
 protected:
  CalibrateIntrinsicsTest() : OutputFolderTest("aerograsp_intrinsics_") {}
};

// The whole path: the renderer draws the board, libapriltag finds its corners,
// OpenCV's calibrateCamera solves; the simulated camera's intrinsics are the truth.
TEST_F(CalibrateIntrinsicsTest, RecoversTheSimulatedCamerasIntrinsics) {
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.out_dir = folder_;
  options.poses = 15;
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("planned 15 views"));
  const nlohmann::json s = Summary();
  const CameraIntrinsics
      truth;  // the D435 colour stream of data/camera (640 x 480, 615, 615, 320, 240)
  ASSERT_EQ(s["factory"]["fx"].get<double>(), truth.fx);
  EXPECT_GE(s["views_used"].get<int>(), 12);
  EXPECT_EQ(s["views_used"].get<int>() + s["views_rejected"].get<int>(), 15);
  // Measured with 15 views on seeds 1-6 (docs/intrinsics.md): the focal lengths within
  // 2.5 px (0.4 %), the principal point within 1.6 px, from corners that
  // libapriltag finds to 0.25-0.31 px rms on the rendered board. The
  // tolerances, 0.75 % and 3 px, leave about twice that.
  EXPECT_NEAR(s["fx"].get<double>(), truth.fx, 0.0075 * truth.fx);
  EXPECT_NEAR(s["fy"].get<double>(), truth.fy, 0.0075 * truth.fy);
  EXPECT_NEAR(s["cx"].get<double>(), truth.cx, 3.0);
  EXPECT_NEAR(s["cy"].get<double>(), truth.cy, 3.0);
  EXPECT_LT(s["rms_px"].get<double>(), 0.5);
  EXPECT_NEAR(s["factory"]["difference_px"]["fx"].get<double>(), s["fx"].get<double>() - truth.fx,
              1e-9);
  ASSERT_EQ(s["dist"].size(), 5u);
  EXPECT_EQ(s["per_view_rms_px"].size(), s["views_used"].get<std::size_t>());
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "views" / "014.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "intrinsics.yaml"));
  // camera.xml reads back as the platform reads its camera (by the platform's camera name).
  const CameraIntrinsics K =
      LoadCameraXml((fs::path(folder_) / "camera.xml").string(), "d435_color");
  EXPECT_NEAR(K.fx, s["fx"].get<double>(), 1e-3);
  EXPECT_NEAR(K.cy, s["cy"].get<double>(), 1e-3);

  // Solving again from the saved views gives the same figures.
  CalibrateCommandOptions again;
  again.resolve_dir = folder_;
  std::ostringstream out2;
  RunCalibrateCommand(again, out2, progress);
  const nlohmann::json s2 = Summary();
  EXPECT_NEAR(s2["fx"].get<double>(), s["fx"].get<double>(), 1e-6);
  EXPECT_NEAR(s2["rms_px"].get<double>(), s["rms_px"].get<double>(), 1e-6);
}

// A dark room (no light at all): the board is never seen.
TEST_F(CalibrateIntrinsicsTest, ABoardNeverSeenSaysSoAndKeepsTheViews) {
  fs::create_directories(folder_);
  std::ifstream in(DataPath("config/world_default.yaml"));
  std::string world((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = world.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    world.replace(at, from.size(), to);
  };
  replace("platform: platform_4dof.yaml", "platform: " + DataPath("config/platform_4dof.yaml"));
  replace("light_intensity: 0.8", "light_intensity: 0.0");
  replace("ambient: 0.35", "ambient: 0.0");
  const std::string world_path = (fs::path(folder_) / "dark.yaml").string();
  std::ofstream(world_path) << world;

  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.out_dir = (fs::path(folder_) / "out").string();
  options.world_config = world_path;
  options.poses = 4;
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(),
                HasSubstr("only 0 usable views of the board (at least 4 needed; 4 rejected"));
    EXPECT_THAT(e.what(), HasSubstr("views.yaml"));
  }
  EXPECT_TRUE(fs::exists(fs::path(options.out_dir) / "views.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(options.out_dir) / "views" / "003.png"));
  std::ifstream views(fs::path(options.out_dir) / "views.yaml");
  const std::string text((std::istreambuf_iterator<char>(views)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("board not seen"));
}

/// A person holding the board in front of the simulated camera: it goes from
/// one pose to the next in 0.15 s (the wizard sees it move) and holds each
/// still for 0.15 s, its centre in each of the image's 3 x 3 cells in turn,
/// 0.52 m away, tilted by 30 deg about x or y (each sign in turn) and rolled a
/// little. After `holds` poses, or when `stop_after` poses were held, it
/// presses Ctrl-C (or types `key` into `keys` when that is given).
class ScriptedHand {
 public:
  explicit ScriptedHand(int holds) : holds_(holds) {}
  void StopAfter(int holds, std::ostream* keys = nullptr) {
    stop_after_ = holds;
    keys_ = keys;
  }

  Eigen::Isometry3d Pose(int i, const CameraIntrinsics& K) const {
    const double fraction[3] = {0.27, 0.5, 0.73};
    const int cell = i % 9;
    const double u = fraction[cell % 3] * K.width, v = fraction[cell / 3] * K.height;
    const double tilt_rad = 30.0 * M_PI / 180.0 * ((i % 4) % 2 == 0 ? 1.0 : -1.0);
    const Eigen::Vector3d axis = (i % 4) < 2 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const double roll_rad = 0.1 * std::sin(1.7 * i);
    Eigen::Isometry3d cMt = Eigen::Isometry3d::Identity();
    cMt.linear() =
        (Eigen::AngleAxisd(tilt_rad, axis) * Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()))
            .toRotationMatrix();
    cMt.translation() = K.Unproject(u, v, 0.52);
    return cMt;
  }

  void operator()(IntrinsicsHardware& hw, double t_s) {
    const CameraIntrinsics& K = hw.camera().intrinsics();
    constexpr double kMove_s = 0.15, kHold_s = 0.15;
    const int i = static_cast<int>(t_s / (kMove_s + kHold_s));
    const double into_s = t_s - i * (kMove_s + kHold_s);
    if (i >= holds_ || (stop_after_ > 0 && i >= stop_after_)) {
      if (stopped_) return;
      stopped_ = true;
      if (keys_) {
        *keys_ << "q\n";
      } else {
        std::raise(SIGINT);
      }
      return;
    }
    const Eigen::Isometry3d from = i == 0 ? Pose(0, K) : Pose(i - 1, K), to = Pose(i, K);
    const double s = std::min(1.0, into_s / kMove_s);
    Eigen::Isometry3d cMt = Eigen::Isometry3d::Identity();
    cMt.linear() = Eigen::Quaterniond(from.linear())
                       .slerp(s, Eigen::Quaterniond(to.linear()))
                       .toRotationMatrix();
    cMt.translation() = (1.0 - s) * from.translation() + s * to.translation();
    hw.world()->MoveAttachment(hw.board_attachment(), cMt);
  }

 private:
  int holds_;
  int stop_after_ = 0;
  std::ostream* keys_ = nullptr;
  bool stopped_ = false;
};

// The whole hand-held path through the hardware factory: the simulated camera
// of data/config/hardware_sim.yaml, whose world carries the board a test's
// hand moves; the wizard takes what it needs and stops on complete coverage.
TEST_F(CalibrateIntrinsicsTest, AHandHeldBoardReachesTheSimulatorsAccuracy) {
  std::ostringstream out;
  const std::unique_ptr<IntrinsicsHardware> hw =
      OpenIntrinsicsHardware(DataPath("config/hardware_sim.yaml"), "", 1, out);
  ScriptedHand hand(40);
  hw->SetSimulatedHand(std::ref(hand));
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.out_dir = folder_;
  options.poses = 15;
  std::istringstream keys;  // nothing typed
  RunHandHeldIntrinsics(options, *hw, keys, out);
  EXPECT_THAT(out.str(), HasSubstr("camera   ok: sim"));
  EXPECT_THAT(out.str(), HasSubstr("sample  1: tilt x +30"));
  EXPECT_THAT(out.str(), HasSubstr("missing: "));
  EXPECT_THAT(out.str(), HasSubstr("sampling stopped (complete coverage): 15 samples; complete"));
  const nlohmann::json s = Summary();
  const CameraIntrinsics truth;
  EXPECT_EQ(s["views_used"].get<int>() + s["views_rejected"].get<int>(), 15);
  EXPECT_GE(s["views_used"].get<int>(), 12);
  // The planned run's tolerances (above).
  EXPECT_NEAR(s["fx"].get<double>(), truth.fx, 0.0075 * truth.fx);
  EXPECT_NEAR(s["fy"].get<double>(), truth.fy, 0.0075 * truth.fy);
  EXPECT_NEAR(s["cx"].get<double>(), truth.cx, 3.0);
  EXPECT_NEAR(s["cy"].get<double>(), truth.cy, 3.0);
  EXPECT_LT(s["rms_px"].get<double>(), 0.5);
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "views" / "014.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "camera.xml"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "board.svg"));
}

TEST_F(CalibrateIntrinsicsTest, CtrlCStopsTheSamplingAndSolvesWithTheSamplesTaken) {
  std::ostringstream out;
  const std::unique_ptr<IntrinsicsHardware> hw =
      OpenIntrinsicsHardware(DataPath("config/hardware_sim.yaml"), "", 1, out);
  ScriptedHand hand(40);
  hand.StopAfter(6);
  hw->SetSimulatedHand(std::ref(hand));
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  std::istringstream keys;
  RunHandHeldIntrinsics(options, *hw, keys, out);
  // Of the six poses held, the first ones each add to the coverage; the later
  // ones repeat what is covered (the wizard skips them).
  EXPECT_THAT(out.str(), HasSubstr("sampling stopped (Ctrl-C): 4 samples; missing: "));
  EXPECT_EQ(Summary()["views_used"].get<int>() + Summary()["views_rejected"].get<int>(), 4);
}

TEST_F(CalibrateIntrinsicsTest, AKeyStopsTheSampling) {
  std::ostringstream out;
  const std::unique_ptr<IntrinsicsHardware> hw =
      OpenIntrinsicsHardware(DataPath("config/hardware_sim.yaml"), "", 1, out);
  std::stringstream keys;
  ScriptedHand hand(40);
  hand.StopAfter(5, &keys);
  hw->SetSimulatedHand(std::ref(hand));
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  RunHandHeldIntrinsics(options, *hw, keys, out);
  EXPECT_THAT(out.str(), HasSubstr("sampling stopped (the keyboard): 4 samples"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "intrinsics.yaml"));
}

TEST_F(CalibrateIntrinsicsTest, ADryRunChecksTheCameraAndRecordsNothing) {
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.dry_run = true;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("ok       camera: frame"));
  EXPECT_THAT(out.str(), HasSubstr("dry run: nothing was recorded"));
  EXPECT_FALSE(fs::exists(folder_));
}

TEST_F(CalibrateIntrinsicsTest, AHandRigsBoardIsTheOneLookedForAndPrinted) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "hand.yaml").string();
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms: {backend: sim}\nautopilot: {backend: sim}\ncamera: {backend: sim}\n"
                      << "calibration:\n  mount: hand\n  board: {family: tag36h11, rows: 3, "
                         "cols: 4, tag_size_m: 0.04, spacing_m: 0.01, margin_m: 0.01}\n";
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.dry_run = true;
  options.hardware_path = path;
  options.out_dir = (fs::path(folder_) / "out").string();
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("hold the 3 x 4 board of 40 mm tags (all 12 tags in view)"));
  EXPECT_TRUE(fs::exists(fs::path(options.out_dir) / "board.svg"));
  EXPECT_FALSE(fs::exists(fs::path(options.out_dir) / "views"));
}

TEST_F(CalibrateIntrinsicsTest, AStillnessThresholdOutOfRangeNamesTheKeyAndTheBound) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "still.yaml").string();
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms: {backend: sim}\nautopilot: {backend: sim}\ncamera: {backend: sim}\n"
                      << "calibration:\n  still_px: 0\n";
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.dry_run = true;
  options.hardware_path = path;
  std::ostringstream out, progress;
  EXPECT_THAT([&] { RunCalibrateCommand(options, out, progress); },
              ::testing::ThrowsMessage<ConfigError>(HasSubstr(
                  path + ": calibration.still_px: 0 px is below the lower bound 0.01 px")));
}

TEST_F(CalibrateIntrinsicsTest, ADryRunWithoutTheRealCameraNamesIt) {
  CalibrateCommandOptions options;
  options.intrinsics = true;
  options.dry_run = true;
  options.hardware_path = DataPath("config/hardware_example.yaml");
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const HardwareError& e) {
    EXPECT_THAT(e.what(), HasSubstr("hardware_example.yaml: the camera did not open; nothing was "
                                    "recorded:\n  camera (realsense): "));
  }
  EXPECT_FALSE(fs::exists(folder_));
}

TEST_F(CalibrateIntrinsicsTest, AMalformedViewsFileNamesTheField) {
  fs::create_directories(folder_);
  std::ofstream(fs::path(folder_) / "views.yaml")
      << "kind: intrinsics\nfactory: {width: 640, height: 480, fx_px: "
         "615, fy_px: 615, cx_px: 320, cy_px: 240}\nboard: {}\nviews:\n"
         "  - {image: a.png, accepted: true, corners: [[1, 2, 3]]}\n";
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("views.yaml: views[0].corners: each corner is x, y, z, u, v"));
  }
}

}  // namespace
}  // namespace aerograsp
