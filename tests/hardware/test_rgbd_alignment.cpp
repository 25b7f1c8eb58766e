#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "hardware/rgbd_alignment.h"
#include "hardware/rgbd_camera.h"
#include "tests/common/simulated_recording.h"

namespace aerograsp {
namespace {
using ::testing::HasSubstr;

StreamCalibration Lens(DistortionModel model) {
  StreamCalibration s;
  s.intrinsics = {640, 480, 600.0, 602.0, 318.0, 243.0};
  s.model = model;
  s.coeffs = {0.12, -0.25, 0.0015, -0.0008, 0.09};
  return s;
}

TEST(LensModelTest, BrownConradyProjectsAsOpenCV) {
  const StreamCalibration s = Lens(DistortionModel::kBrownConrady);
  const cv::Matx33d K(600.0, 0.0, 318.0, 0.0, 602.0, 243.0, 0.0, 0.0, 1.0);
  std::vector<cv::Point3d> points;
  for (double x : {-0.3, 0.0, 0.25})
    for (double y : {-0.2, 0.1, 0.3}) points.emplace_back(x, y, 0.8);
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K,
                    std::vector<double>(s.coeffs.begin(), s.coeffs.end()), pixels);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d px = s.Project({points[i].x, points[i].y, points[i].z});
    EXPECT_NEAR(px.x(), pixels[i].x, 1e-9);
    EXPECT_NEAR(px.y(), pixels[i].y, 1e-9);
  }
}

TEST(LensModelTest, DeprojectInvertsProjectForEveryModel) {
  for (DistortionModel model :
       {DistortionModel::kNone, DistortionModel::kBrownConrady,
        DistortionModel::kModifiedBrownConrady, DistortionModel::kInverseBrownConrady}) {
    const StreamCalibration s = Lens(model);
    for (double u : {3.0, 200.0, 318.0, 630.0}) {
      for (double v : {5.0, 243.0, 470.0}) {
        const Eigen::Vector3d p = s.Deproject(u, v, 1.3);
        EXPECT_DOUBLE_EQ(p.z(), 1.3);
        const Eigen::Vector2d px = s.Project(p);
        EXPECT_NEAR(px.x(), u, 1e-6) << ToString(model);
        EXPECT_NEAR(px.y(), v, 1e-6) << ToString(model);
      }
    }
  }
  // The models differ where there is distortion.
  const Eigen::Vector3d p(0.3, -0.2, 1.0);
  EXPECT_GT((Lens(DistortionModel::kBrownConrady).Project(p) -
             Lens(DistortionModel::kModifiedBrownConrady).Project(p))
                .norm(),
            1e-3);
}

TEST(LensModelTest, NamesParseAndUnknownOnesAreRefusedByName) {
  EXPECT_EQ(ParseDistortionModel("Brown Conrady", "f"), DistortionModel::kBrownConrady);
  EXPECT_EQ(ParseDistortionModel("plumb_bob", "f"), DistortionModel::kBrownConrady);
  EXPECT_EQ(ParseDistortionModel("Inverse Brown Conrady", "f"),
            DistortionModel::kInverseBrownConrady);
  EXPECT_EQ(ParseDistortionModel("", "f"), DistortionModel::kNone);
  for (DistortionModel m :
       {DistortionModel::kNone, DistortionModel::kBrownConrady,
        DistortionModel::kModifiedBrownConrady, DistortionModel::kInverseBrownConrady})
    EXPECT_EQ(ParseDistortionModel(ToString(m), "f"), m);
  EXPECT_THAT([] { ParseDistortionModel("Kannala Brandt4", "rec.bag: camera_info"); },
              ::testing::ThrowsMessage<HardwareError>(
                  HasSubstr("rec.bag: camera_info: distortion model 'Kannala Brandt4' is not "
                            "supported")));
}

TEST(FramePairingTest, EachColourFrameTakesTheNearestDepthFrameWithinTheGap) {
  const std::vector<double> color = {0.00, 0.033, 0.067, 0.100, 0.500};
  const std::vector<double> depth = {0.005, 0.040, 0.095, 0.130};
  EXPECT_NEAR(MedianInterval(depth), 0.035, 1e-12);
  EXPECT_EQ(PairByStamp(color, depth, 0.02), (std::vector<int>{0, 1, -1, 2, -1}));
  EXPECT_EQ(PairByStamp(color, depth, 1.0), (std::vector<int>{0, 1, 1, 2, 3}));
}

/// Depth rendered from the depth camera and aligned agrees with depth rendered
/// from the colour camera within the quantisation (1 unit, and the depth change
/// across one depth pixel on a slanted surface), except at depth edges.
TEST(DepthAlignmentTest, AlignedDepthCameraImageAgreesWithTheColourCameraRender) {
  const testing::SimulatedRecording r = testing::SimulateRecording(1);
  const testing::SimulatedFrame& f = r.frames[0];
  const DepthImage aligned =
      AlignDepthToColor(f.depth, r.depth, r.color, r.colorMdepth, r.depth_scale_m);
  ASSERT_EQ(aligned.width, 640);
  const double color_per_depth_px = r.color.intrinsics.fx / r.depth.intrinsics.fx;
  int compared = 0, within = 0, holes = 0, exact = 0;
  for (int v = 2; v < 478; ++v) {
    for (int u = 2; u < 638; ++u) {
      const int truth = f.color_depth.at(u, v);
      if (truth == 0) continue;
      // Not at an edge: the 5x5 neighbourhood is continuous.
      bool edge = false;
      for (int dv = -2; dv <= 2 && !edge; ++dv)
        for (int du = -2; du <= 2 && !edge; ++du)
          edge = std::abs(int(f.color_depth.at(u + du, v + dv)) - truth) > 10;
      if (edge) continue;
      ++compared;
      const int got = aligned.at(u, v);
      if (got == 0) {
        ++holes;
        continue;
      }
      // Depth change per colour pixel (units), from central differences of the truth.
      const double slope =
          0.5 * std::max(std::abs(f.color_depth.at(u + 1, v) - f.color_depth.at(u - 1, v)),
                         std::abs(f.color_depth.at(u, v + 1) - f.color_depth.at(u, v - 1)));
      const int error = std::abs(got - truth);
      within += error <= 1 + std::ceil(slope * color_per_depth_px);
      exact += error <= 1;
    }
  }
  ASSERT_GT(compared, 100000);
  // A few holes where the colour camera sees what the depth camera does not (its field of view).
  EXPECT_LT(holes, compared / 50) << holes << " of " << compared;
  EXPECT_GT(within, 0.995 * (compared - holes)) << within << " of " << compared - holes;
  EXPECT_GT(exact, 0.8 * (compared - holes)) << exact << " of " << compared - holes;
}

/// The wrong direction of the extrinsic (its inverse) moves the depth edges by pixels.
TEST(DepthAlignmentTest, TheExtrinsicsDirectionMatters) {
  const testing::SimulatedRecording r = testing::SimulateRecording(1);
  const testing::SimulatedFrame& f = r.frames[0];
  auto mismatched = [&](const Eigen::Isometry3d& colorMdepth) {
    const DepthImage a = AlignDepthToColor(f.depth, r.depth, r.color, colorMdepth, 0.001);
    int bad = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i)
      bad += a.data[i] && f.color_depth.data[i] && std::abs(a.data[i] - f.color_depth.data[i]) > 10;
    return bad;
  };
  EXPECT_GT(mismatched(r.colorMdepth.inverse()), 5 * mismatched(r.colorMdepth) + 100);
}

TEST(DepthAlignmentTest, ADepthImageOfAnotherSizeIsRefused) {
  const testing::SimulatedRecording r = testing::D435LikeStreams();
  EXPECT_THAT(
      [&] { AlignDepthToColor(DepthImage(320, 240), r.depth, r.color, r.colorMdepth, 0.001); },
      ::testing::ThrowsMessage<HardwareError>(HasSubstr("320x240, its intrinsics say 640x480")));
}

}  // namespace
}  // namespace aerograsp
