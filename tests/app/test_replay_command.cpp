#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/commands/record_command.h"
#include "app/commands/replay_command.h"
#include "app/exit_codes.h"
#include "core/config.h"
#include "core/transforms.h"
#include "hardware/rgbd_camera.h"
#include "tests/app/headless_browser.h"
#include "tests/common/earlier_report.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// Records a few frames of the default world once for all tests here.
class ReplayCommandTest : public ::testing::Test {
 protected:
  // Folders named by process: ctest runs each test in its own process, in parallel.
  static void SetUpTestSuite() {
    sequence_ =
        (fs::temp_directory_path() / ("aerograsp_replay_test_seq_" + std::to_string(getpid())))
            .string();
    fs::remove_all(sequence_);
    RecordCommandOptions record;
    record.out_dir = sequence_;
    record.frames = 8;
    record.seed = 23;
    record.motion = "crawl";
    std::ostringstream out, progress;
    RunRecordCommand(record, out, progress);
  }
  static void TearDownTestSuite() { fs::remove_all(sequence_); }
  void SetUp() override {
    out_dir_ =
        (fs::temp_directory_path() / ("aerograsp_replay_test_out_" + std::to_string(getpid())))
            .string();
    fs::remove_all(out_dir_);
    options_.sequence = sequence_;
    options_.out_dir = out_dir_;
  }
  void TearDown() override { fs::remove_all(out_dir_); }
  nlohmann::json Run() {
    std::ostringstream out, progress;
    exit_code_ = RunReplayCommand(options_, out, progress);
    std::ifstream file(fs::path(out_dir_) / "summary.json");
    return nlohmann::json::parse(file);
  }
  static std::string sequence_;
  std::string out_dir_;
  ReplayCommandOptions options_;
  int exit_code_ = -1;
};
std::string ReplayCommandTest::sequence_;

TEST_F(ReplayCommandTest, TracksTheRecordedObjectAndWritesTheReport) {
  const nlohmann::json s = Run();
  EXPECT_EQ(exit_code_, kExitOk);
  EXPECT_EQ(s["frames"], 8);
  EXPECT_EQ(s["object"], "crawler");
  for (const char* key :
       {"detection_recall", "translation_rmse_m", "rotation_rmse_deg", "add_s_recall",
        "frame_ms_median", "frame_ms_p95", "stage_ms", "visp_peer"}) {
    EXPECT_TRUE(s.contains(key)) << key;
  }
  EXPECT_GE(s["frames_found"].get<int>(), 6);  // found from the second frame (hysteresis)
  ASSERT_TRUE(s["translation_rmse_m"].is_number());
  EXPECT_LT(s["translation_rmse_m"].get<double>(), 0.01);
  EXPECT_LT(s["rotation_rmse_deg"].get<double>(), 3.0);
  EXPECT_TRUE(s["stage_ms"]["crop_cloud_normals"]["median"].is_number());
  EXPECT_TRUE(s["visp_peer"]["initialised"].get<bool>());
  EXPECT_TRUE(fs::exists(fs::path(out_dir_) / "pose_vs_truth.png"));
  std::ifstream page(fs::path(out_dir_) / "index.html");
  std::stringstream html;
  html << page.rdbuf();
  // x, y, z, the rotation error and found, ours and the peer's in each.
  EXPECT_EQ(CountCharts(html.str()), 5);
  EXPECT_THAT(html.str(), ::testing::HasSubstr("\"name\":\"ViSP mbt (dense depth)\""));
  std::ifstream poses(fs::path(out_dir_) / "poses.csv");
  std::string line;
  int lines = 0;
  while (std::getline(poses, line)) ++lines;
  EXPECT_EQ(lines, 9);
}

TEST_F(ReplayCommandTest, AKnownFirstPoseNeedsNoGlobalRegistration) {
  options_.init_from_truth = true;
  options_.run_peer = false;
  options_.max_frames = 4;
  const nlohmann::json s = Run();
  EXPECT_EQ(s["frames"], 4);
  EXPECT_EQ(s["global_inits"], 0);
  EXPECT_FALSE(s.contains("visp_peer"));
  EXPECT_LT(s["translation_rmse_m"].get<double>(), 0.01);
}

TEST_F(ReplayCommandTest, ATruncatedSequenceIsReportedNotFatal) {
  const std::string copy =
      (fs::temp_directory_path() / ("aerograsp_replay_test_trunc_" + std::to_string(getpid())))
          .string();
  fs::remove_all(copy);
  fs::copy(sequence_, copy, fs::copy_options::recursive);
  // Frame 3's colour image cut short, as by a full disk.
  const fs::path png = fs::path(copy) / "color" / "000003.png";
  fs::resize_file(png, 100);
  options_.sequence = copy;
  options_.run_peer = false;
  const nlohmann::json s = Run();
  EXPECT_EQ(exit_code_, kExitStoppedEarly);
  EXPECT_EQ(s["frames"], 3);
  ASSERT_TRUE(s.contains("stopped_early"));
  EXPECT_THAT(s["stopped_early"].get<std::string>(), HasSubstr("000003.png"));
  // A missing image is found when the sequence is opened: the report of the
  // run before stays whole, nothing of this run beside it.
  fs::remove(png);
  options_.overwrite = true;
  EXPECT_THROW(Run(), HardwareError);
  std::ifstream earlier(fs::path(out_dir_) / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(earlier)["frames"], 3);
  testing::ExpectNothingBeside(out_dir_);
  fs::remove_all(copy);
}

TEST_F(ReplayCommandTest, TheFilterRunsInTheWorldWithTheRecordedVehicleStates) {
  options_.run_peer = false;
  options_.filter_frame = "world";
  const nlohmann::json s = Run();
  EXPECT_EQ(s["filter_frame"], "world");
  EXPECT_GE(s["frames_found"].get<int>(), 6);
  EXPECT_LT(s["translation_rmse_m"].get<double>(), 0.01);
  // Without vehicle states the world frame cannot be had: said, not guessed.
  const std::string copy =
      (fs::temp_directory_path() / ("aerograsp_replay_test_novehicle_" + std::to_string(getpid())))
          .string();
  fs::remove_all(copy);
  fs::copy(sequence_, copy, fs::copy_options::recursive);
  fs::remove(fs::path(copy) / "vehicle.csv");
  options_.sequence = copy;
  options_.overwrite = true;  // the report above
  EXPECT_THAT([&] { Run(); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("vehicle.csv")));
  options_.filter_frame = "body";
  EXPECT_THAT([&] { Run(); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("--filter-frame")));
  fs::remove_all(copy);
}

TEST_F(ReplayCommandTest, AnObjectFullyHiddenIsFoundAgainWithinFiveFramesOfReappearing) {
  // Frames 6-11 hidden by a panel in front of the camera, then 10 frames in view.
  const std::string hidden =
      (fs::temp_directory_path() / ("aerograsp_replay_test_hidden_" + std::to_string(getpid())))
          .string();
  fs::remove_all(hidden);
  RecordCommandOptions record;
  record.out_dir = hidden;
  record.frames = 22;
  record.seed = 23;
  record.motion = "crawl";
  record.occlude_at_s = 0.19;
  record.occlude_for_s = 0.2;
  std::ostringstream record_out, progress;
  RunRecordCommand(record, record_out, progress);
  options_.sequence = hidden;
  const nlohmann::json s =
      Run();  // with ViSP's tracker beside ours: it must survive the hidden frames too
  fs::remove_all(hidden);
  EXPECT_EQ(s["reacquisitions"], 1);
  EXPECT_EQ(s["never_reacquired"], 0);
  EXPECT_GE(s["reacquire_max_frames"].get<int>(), 1);
  EXPECT_LE(s["reacquire_max_frames"].get<int>(), 5);
  EXPECT_EQ(s["frames_visible"], 16);
  EXPECT_LT(s["translation_rmse_m"].get<double>(), 0.01);
}

TEST_F(ReplayCommandTest, AnEarlierReportIsRefusedAndReplacedWithOverwrite) {
  options_.init_from_truth = true;
  options_.run_peer = false;
  options_.max_frames = 2;
  testing::ExpectRefusesAnEarlierReport([&] { Run(); }, out_dir_);
  options_.overwrite = true;
  EXPECT_EQ(Run()["frames"], 2);
  testing::ExpectReplacedTheEarlierReport(out_dir_);
  EXPECT_TRUE(fs::exists(fs::path(out_dir_) / "poses.csv"));
}

TEST_F(ReplayCommandTest, AMissingOrCorruptModelIsAClearError) {
  options_.object = "no_such_object";
  EXPECT_THAT([&] { Run(); }, ::testing::Throws<std::exception>());
  options_.object = "";
  options_.detector =
      (fs::temp_directory_path() / ("aerograsp_bad_detector_" + std::to_string(getpid()) + ".onnx"))
          .string();
  std::ofstream(options_.detector) << "garbage";
  EXPECT_THAT([&] { Run(); }, ::testing::ThrowsMessage<std::runtime_error>(
                                  HasSubstr("cannot load the detector model")));
  fs::remove(options_.detector);
}

TEST_F(ReplayCommandTest, APerceptionFileTunesThePipeline) {
  options_.init_from_truth = true;
  options_.run_peer = false;
  options_.perception_config = (fs::temp_directory_path() / ("aerograsp_replay_perception_" +
                                                             std::to_string(getpid()) + ".yaml"))
                                   .string();
  std::ofstream(options_.perception_config) << "track:\n  frames_to_find: 5\n";
  const nlohmann::json s = Run();
  EXPECT_EQ(s["perception"], options_.perception_config);
  EXPECT_EQ(s["frames_found"], 4);  // from the fifth of 8 frames, not the second
  // A bad file is named with the key and its bound before the sequence is read.
  std::ofstream(options_.perception_config) << "icp:\n  max_iterations: 0\n";
  options_.sequence = "/no/such/sequence";
  EXPECT_THAT([&] { Run(); },
              ::testing::ThrowsMessage<ConfigError>(HasSubstr(
                  options_.perception_config + ": icp.max_iterations: must be in [1, 100]")));
  fs::remove(options_.perception_config);
}

TEST(ParsePoseTest, ReadsSevenNumbersAndRejectsTheRest) {
  const Eigen::Isometry3d cMo = ParsePose("0.1 -0.2 0.7 0 1 0 0");
  EXPECT_TRUE(cMo.translation().isApprox(Eigen::Vector3d(0.1, -0.2, 0.7)));
  EXPECT_NEAR(RotationAngle(cMo.linear()), M_PI, 1e-12);
  EXPECT_THAT([] { ParsePose("0 0 1 1 0 0"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("expected 7 numbers")));
  EXPECT_THAT([] { ParsePose("0 0 1 0 0 0 0"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("quaternion is zero")));
  EXPECT_THAT([] { ParsePose("0 0 x 1 0 0 0"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("'x' is not a number")));
}

}  // namespace
}  // namespace aerograsp
