#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/config.h"
#include "core/data_dir.h"
#include "core/transforms.h"
#include "hardware/tum_folder.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A TUM RGB-D folder of 3 colour frames at 30 Hz, depth 5 ms later, and a camera trajectory.
class TumFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = (fs::temp_directory_path() / (std::string("aerograsp_tum_") + test->name())).string();
    fs::remove_all(folder_);
    fs::create_directories(fs::path(folder_) / "rgb");
    fs::create_directories(fs::path(folder_) / "depth");
    std::ofstream rgb(fs::path(folder_) / "rgb.txt"), depth(fs::path(folder_) / "depth.txt");
    rgb << "# color images\n# timestamp filename\n";
    depth << "# depth maps\n";
    for (int i = 0; i < 3; ++i) {
      const double t = 100.0 + i / 30.0;
      const std::string name = std::to_string(i) + ".png";
      cv::imwrite((fs::path(folder_) / "rgb" / name).string(),
                  cv::Mat(24, 32, CV_8UC3, cv::Scalar(10 * i, 20, 30)));
      cv::imwrite((fs::path(folder_) / "depth" / name).string(),
                  cv::Mat(24, 32, CV_16UC1, cv::Scalar(5000 + i)));
      rgb << std::fixed << t << " rgb/" << name << "\n";
      depth << std::fixed << t + 0.005 << " depth/" << name << "\n";
    }
    // The camera moves 0.3 m/s along x, no rotation.
    std::ofstream truth(fs::path(folder_) / "groundtruth.txt");
    truth << "# timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i <= 20; ++i)
      truth << std::fixed << 99.99 + 0.01 * i << " " << 0.003 * i << " 0 0 0 0 0 1\n";
    options_.intrinsics = CameraIntrinsics{32, 24, 30.0, 30.0, 15.5, 11.5};
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string folder_;
  TumOptions options_;
};

TEST_F(TumFolderTest, PairsFramesByTimeAndScalesDepth) {
  TumCamera tum(folder_, options_);
  EXPECT_EQ(tum.info().frame_count, 3);
  EXPECT_NEAR(tum.info().frame_rate_hz, 30.0, 1e-3);
  EXPECT_DOUBLE_EQ(tum.depth_scale_m(), 0.0002);
  EXPECT_FALSE(tum.has_groundtruth());
  RgbdFrame frame;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(tum.Grab(&frame));
    EXPECT_NEAR(frame.stamp_s, 100.0 + i / 30.0, 1e-6);
    EXPECT_EQ(frame.depth.at(3, 4), 5000 + i);  // 1 m
    EXPECT_EQ(frame.color.at(0, 0, 0), 30);     // RGB from OpenCV's BGR
    EXPECT_EQ(frame.color.at(0, 0, 2), 10 * i);
  }
  EXPECT_FALSE(tum.Grab(&frame));
}

TEST_F(TumFolderTest, TheCameraTrajectoryGivesTheObjectsTruth) {
  options_.wMo = MakeTransform(Eigen::Vector3d(0.1, 0.0, 1.0), Eigen::Vector3d(0.0, 0.0, 0.3));
  TumCamera tum(folder_, options_);
  ASSERT_TRUE(tum.has_groundtruth());
  // At t = 100 + 1/30 the camera is at x = 0.3 * (1/30 + 0.01) (interpolated).
  const Eigen::Isometry3d cMo = *tum.extras(1).cMo;
  EXPECT_NEAR(cMo.translation().x(), 0.1 - 0.3 * (1.0 / 30.0 + 0.01), 1e-6);  // stamps to 1 us
  EXPECT_NEAR(cMo.translation().z(), 1.0, 1e-12);
}

TEST_F(TumFolderTest, MissingIntrinsicsAndBadLinesAreNamed) {
  options_.intrinsics.reset();
  EXPECT_THAT([&] { TumCamera tum(folder_, options_); },
              ::testing::ThrowsMessage<HardwareError>(
                  HasSubstr("carries no camera intrinsics; give them with --intrinsics FILE")));
  options_.intrinsics = CameraIntrinsics{32, 24, 30.0, 30.0, 15.5, 11.5};
  std::ofstream(fs::path(folder_) / "depth.txt", std::ios::app) << "100.2\n";
  EXPECT_THAT([&] { TumCamera tum(folder_, options_); },
              ::testing::ThrowsMessage<HardwareError>(
                  HasSubstr("depth.txt: line 5: 1 fields, expected 2")));
}

TEST_F(TumFolderTest, AnImageOfAnotherSizeIsNamed) {
  options_.intrinsics = CameraIntrinsics{64, 48, 60.0, 60.0, 31.5, 23.5};
  TumCamera tum(folder_, options_);
  RgbdFrame frame;
  EXPECT_THAT([&] { tum.Grab(&frame); }, ::testing::ThrowsMessage<HardwareError>(HasSubstr(
                                             "0.png: is 32x24, the intrinsics say 64x48")));
}

TEST_F(TumFolderTest, IntrinsicsComeFromVispXmlOrYaml) {
  const fs::path yaml = fs::path(folder_) / "camera.yaml";
  std::ofstream(yaml)
      << "intrinsics: {width: 32, height: 24, fx: 30, fy: 31, cx: 15.5, cy: 11.5}\n";
  EXPECT_EQ(LoadIntrinsicsFile(yaml.string()).fy, 31.0);
  EXPECT_EQ(LoadIntrinsicsFile(DataPath("camera/d435_color_640x480.xml")).width, 640);
  EXPECT_THAT(
      [&] { LoadIntrinsicsFile((fs::path(folder_) / "rgb.txt").string()); },
      ::testing::ThrowsMessage<ConfigError>(HasSubstr("rgb.txt: intrinsics are read from")));
}

}  // namespace
}  // namespace aerograsp
