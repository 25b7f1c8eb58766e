#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "calib/intrinsics_calibration.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {
using ::testing::HasSubstr;

std::vector<IntrinsicsView> ExactViews(const CameraIntrinsics& K, int count) {
  TagBoardConfig board;
  board.rows = 4;
  board.cols = 5;
  board.tag_size_m = 0.03;
  std::vector<IntrinsicsView> views;
  for (int i = 0; i < count; ++i) {
    const double axis = 2.4 * i;  // tilts about well separated axes
    const Eigen::Isometry3d cMt =
        MakeTransform(Eigen::Vector3d(0.02 * std::cos(i), 0.02 * std::sin(i), 0.35 + 0.03 * i),
                      0.5 * Eigen::Vector3d(std::cos(axis), std::sin(axis), 0.1));
    IntrinsicsView view;
    for (const BoardTag& tag : BoardTags(board)) {
      for (const Eigen::Vector3d& p_t : tag.corners_t)
        view.corners.emplace_back(p_t, K.Project(cMt * p_t));
    }
    views.push_back(view);
  }
  return views;
}

TEST(IntrinsicsCalibrationTest, ExactCornersGiveTheCameraBack) {
  CameraIntrinsics K;
  K.fx = 600.0;
  K.fy = 610.0;
  K.cx = 325.0;
  K.cy = 236.0;
  const IntrinsicsResult r = CalibrateIntrinsics(ExactViews(K, 6), K.width, K.height);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NEAR(r.K.fx, K.fx, 1e-2);
  EXPECT_NEAR(r.K.fy, K.fy, 1e-2);
  EXPECT_NEAR(r.K.cx, K.cx, 1e-2);
  EXPECT_NEAR(r.K.cy, K.cy, 1e-2);
  for (double d : r.distortion) EXPECT_NEAR(d, 0.0, 1e-4);
  EXPECT_LT(r.rms_px, 1e-3);
  EXPECT_EQ(r.per_view_rms_px.size(), 6u);
}

TEST(IntrinsicsCalibrationTest, TooFewViewsSaySo) {
  const IntrinsicsResult r = CalibrateIntrinsics(ExactViews(CameraIntrinsics{}, 3), 640, 480, 4);
  EXPECT_FALSE(r.ok);
  EXPECT_THAT(r.message, HasSubstr("only 3 views (at least 4 needed)"));
}

}  // namespace
}  // namespace aerograsp
