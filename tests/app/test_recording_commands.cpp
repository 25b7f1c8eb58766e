#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/commands/convert_command.h"
#include "app/commands/replay_command.h"
#include "core/config.h"
#include "core/transforms.h"
#include "hardware/bag/realsense_bag.h"
#include "tests/common/simulated_recording.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A realsense-layout bag of the simulated D435 (unaligned depth, a known
/// extrinsic, the object at a known pose), written once for the tests here.
class RecordingCommandsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("aerograsp_recordings_" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    // u_shape: no direction along which ICP may slide, so the pose is fully observable.
    recording_ = new testing::SimulatedRecording(testing::SimulateRecording(6, "u_shape"));
    WriteBag((root_ / "sim.bag").string(), 6);
  }
  static void TearDownTestSuite() {
    delete recording_;
    fs::remove_all(root_);
  }
  /// The first `frames` frames; colour at 30 Hz, depth 3 ms later; frame `odd`
  /// (if any) with a colour image of half the size.
  static void WriteBag(const std::string& path, int frames, int odd = -1) {
    RealsenseBagWriter::Streams s;
    s.color = recording_->color;
    s.depth = recording_->depth;
    s.colorMdepth = recording_->colorMdepth;
    s.depth_scale_m = recording_->depth_scale_m;
    RealsenseBagWriter writer(path, s);
    for (int i = 0; i < frames; ++i) {
      const double t = 2.0 + i / 30.0;
      writer.WriteColor(t, i == odd ? ColorImage(320, 240) : recording_->frames[i].color);
      writer.WriteDepth(t + 0.003, recording_->frames[i].depth);
    }
  }
  static std::string bag() { return (root_ / "sim.bag").string(); }

  static fs::path root_;
  static testing::SimulatedRecording* recording_;
};
fs::path RecordingCommandsTest::root_;
testing::SimulatedRecording* RecordingCommandsTest::recording_ = nullptr;

/// poses.csv's cMo of every frame.
std::vector<Eigen::Isometry3d> ReadPoses(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<Eigen::Isometry3d> poses;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    std::string cell;
    for (int i = 0; i < 9 && std::getline(ss, cell, ','); ++i) v.push_back(std::stod(cell));
    poses.push_back(MakeTransformWxyz(Eigen::Vector3d(v[2], v[3], v[4]),
                                      Eigen::Vector4d(v[5], v[6], v[7], v[8])));
  }
  return poses;
}

TEST_F(RecordingCommandsTest, ReplayOfABagRecoversTheObjectPose) {
  ReplayCommandOptions options;
  options.sequence = bag();
  options.out_dir = (root_ / "replay").string();
  options.object = recording_->object;
  options.run_peer = false;
  // Started 5 mm and 3 degrees off the truth.
  options.init_cMo = recording_->frames[0].cMo * MakeTransform(Eigen::Vector3d(0.004, -0.003, 0.0),
                                                               Eigen::Vector3d(0.03, 0.0, 0.04));
  std::ostringstream out, progress;
  RunReplayCommand(options, out, progress);
  const std::vector<Eigen::Isometry3d> poses = ReadPoses(root_ / "replay" / "poses.csv");
  ASSERT_EQ(poses.size(), 6u);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const PoseError e = ComparePoses(recording_->frames[i].cMo, poses[i]);
    EXPECT_LT(e.translation_m, 0.002) << "frame " << i;
    EXPECT_LT(e.rotation_rad * 180.0 / M_PI, 1.0) << "frame " << i;
  }
}

TEST_F(RecordingCommandsTest, ConvertWritesTheBagAsASequenceThatReplaysTheSameFrames) {
  ConvertCommandOptions options;
  options.input = bag();
  options.out_dir = (root_ / "converted").string();
  options.object = recording_->object;
  std::ostringstream out, progress;
  RunConvertCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("convert: 6 frames"));
  ReplayCamera sequence(options.out_dir);
  EXPECT_EQ(sequence.info().object, recording_->object);
  EXPECT_EQ(sequence.info().color_model, DistortionModel::kBrownConrady);
  RealsenseBagCamera original(bag());
  RgbdFrame a, b;
  while (original.Grab(&a)) {
    ASSERT_TRUE(sequence.Grab(&b));
    EXPECT_EQ(a.color, b.color);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_DOUBLE_EQ(a.stamp_s, b.stamp_s);
  }
  EXPECT_FALSE(sequence.Grab(&b));
  // Not over a sequence unless asked.
  EXPECT_THAT([&] { RunConvertCommand(options, out, progress); },
              ::testing::ThrowsMessage<ConfigError>(
                  HasSubstr(": holds an earlier report; --overwrite replaces it")));
  options.overwrite = true;
  options.max_frames = 2;
  RunConvertCommand(options, out, progress);
  EXPECT_EQ(ReadSequenceInfo(options.out_dir).frame_count, 2);
}

TEST_F(RecordingCommandsTest, AFailedConversionLeavesNothingBehind) {
  const std::string bad = (root_ / "odd.bag").string();
  WriteBag(bad, 4, /*odd=*/2);
  ConvertCommandOptions options;
  options.input = bad;
  options.out_dir = (root_ / "odd_sequence").string();
  std::ostringstream out, progress;
  EXPECT_THAT([&] { RunConvertCommand(options, out, progress); },
              ::testing::ThrowsMessage<HardwareError>(
                  HasSubstr("odd.bag: /device_0/sensor_1/Color_0/image/data message 2: the colour "
                            "image is 320x240, its camera_info says 640x480")));
  EXPECT_FALSE(fs::exists(options.out_dir));
  for (const auto& entry : fs::directory_iterator(root_))
    EXPECT_EQ(entry.path().filename().string().find("partial"), std::string::npos) << entry.path();
  // Nor over a folder that is not a sequence.
  fs::create_directories(fs::path(options.out_dir) / "photos");
  options.input = bag();
  EXPECT_THAT([&] { RunConvertCommand(options, out, progress); },
              ::testing::ThrowsMessage<ConfigError>(HasSubstr(
                  "is not empty and holds no report (no sequence.yaml); choose another folder")));
  EXPECT_TRUE(fs::exists(fs::path(options.out_dir) / "photos"));
}

}  // namespace
}  // namespace aerograsp
