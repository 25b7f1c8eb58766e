#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "calib/coverage.h"
#include "calib/intrinsics_calibration.h"
#include "core/config.h"
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

// ---- coverage of hand-held samples ----

/// A block of `n` x `n` corners 10 px apart with its top-left corner at (u, v).
CoverageSample Block(double u, double v, int n, double tilt_x_deg = 0.0, double tilt_y_deg = 0.0) {
  CoverageSample s;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) s.pixels.emplace_back(u + 10.0 * j, v + 10.0 * i);
  s.tilt_x_deg = tilt_x_deg;
  s.tilt_y_deg = tilt_y_deg;
  return s;
}

TEST(CoverageTest, ACellIsCoveredByEnoughCornersOnly) {
  const CoverageConfig config;  // 3 x 3, 4 corners a cell
  // 640 x 480: cells of 213 x 160 px. A 2 x 2 block in the top-left cell covers it...
  EXPECT_EQ(CoverSample(Block(10, 10, 2), 640, 480, config).cells, std::vector<int>{0});
  // ...a block straddling the top-left and top cells covers both with 2 x 4 corners each...
  CoverageSample straddle = Block(195, 10, 4);  // columns at 195, 205 | 215, 225
  EXPECT_EQ(CoverSample(straddle, 640, 480, config).cells, (std::vector<int>{0, 1}));
  // ...and 3 corners in the bottom-right cell do not cover it.
  CoverageSample few;
  few.pixels = {{600, 450}, {610, 450}, {620, 450}};
  EXPECT_TRUE(CoverSample(few, 640, 480, config).cells.empty());
}

TEST(CoverageTest, PixelsOutsideTheImageAreIgnored) {
  CoverageSample outside;
  for (int i = 0; i < 10; ++i) outside.pixels.emplace_back(-5.0 - i, 700.0);
  const SampleCoverage c = CoverSample(outside, 640, 480, CoverageConfig());
  EXPECT_TRUE(c.cells.empty());
  EXPECT_EQ(c.signature.x(), -1);
}

TEST(CoverageTest, TiltsBeyondTheLimitFillTheirBinBySign) {
  const CoverageConfig config;  // 20 deg
  EXPECT_TRUE(CoverSample(Block(300, 200, 2, 19.9, -19.9), 640, 480, config).tilts.empty());
  const SampleCoverage c = CoverSample(Block(300, 200, 2, 25.0, -21.0), 640, 480, config);
  EXPECT_EQ(c.tilts, (std::vector<TiltBin>{TiltBin::kXPositive, TiltBin::kYNegative}));
  EXPECT_EQ(c.signature, Eigen::Vector3i(4, 1, -1));  // centre cell, x +, y -
}

TEST(CoverageTest, ASampleAddsANewCellATiltOrANewSignatureOnly) {
  const CoverageConfig config;
  Coverage coverage = EmptyCoverage(config);
  const SampleCoverage first = CoverSample(Block(10, 10, 2, 25.0, 0.0), 640, 480, config);
  EXPECT_TRUE(AddsToCoverage(coverage, first));
  AddToCoverage(first, &coverage);
  // The same place and tilt again: nothing new.
  EXPECT_FALSE(
      AddsToCoverage(coverage, CoverSample(Block(20, 20, 2, 30.0, 0.0), 640, 480, config)));
  // The same place, a tilt bin not covered yet.
  EXPECT_TRUE(
      AddsToCoverage(coverage, CoverSample(Block(10, 10, 2, -25.0, 0.0), 640, 480, config)));
  // The same place and tilt bins as a second sample, but facing the camera: a new signature.
  EXPECT_TRUE(AddsToCoverage(coverage, CoverSample(Block(10, 10, 2, 0.0, 0.0), 640, 480, config)));
  // A new cell.
  EXPECT_TRUE(
      AddsToCoverage(coverage, CoverSample(Block(600, 450, 2, 25.0, 0.0), 640, 480, config)));
}

TEST(CoverageTest, TheFeedbackNamesTheMissingCellsAndTilts) {
  const CoverageConfig config;
  Coverage coverage = EmptyCoverage(config);
  EXPECT_EQ(CoverageFeedback(coverage, config),
            "missing: top-left, top, top-right, left, centre, right, bottom-left, bottom, "
            "bottom-right; tilt about x > 20 deg, tilt about x < -20 deg, tilt about y > 20 deg, "
            "tilt about y < -20 deg");
  // Every cell but the top-left and the bottom-right, tilted every way but x > 20 deg.
  const double u[3] = {10, 220, 440}, v[3] = {10, 170, 330};
  const double tilts[9][2] = {{0, 0}, {-25, 0}, {0, 25}, {0, -25}, {0, 0},
                              {0, 0}, {0, 0},   {0, 0},  {0, 0}};
  for (int cell = 0; cell < 9; ++cell) {
    if (cell == 0 || cell == 8) continue;
    AddToCoverage(CoverSample(Block(u[cell % 3], v[cell / 3], 2, tilts[cell][0], tilts[cell][1]),
                              640, 480, config),
                  &coverage);
  }
  EXPECT_FALSE(coverage.Complete());
  EXPECT_EQ(CoverageFeedback(coverage, config),
            "missing: top-left, bottom-right; tilt about x > 20 deg");
  AddToCoverage(CoverSample(Block(10, 10, 2, 25, 0), 640, 480, config), &coverage);
  EXPECT_EQ(CoverageFeedback(coverage, config), "missing: bottom-right");
  AddToCoverage(CoverSample(Block(600, 450, 2), 640, 480, config), &coverage);
  EXPECT_TRUE(coverage.Complete());
  EXPECT_EQ(CoverageFeedback(coverage, config), "complete");
}

TEST(CoverageTest, OtherGridsNameTheirCellsByRowAndColumn) {
  CoverageConfig config;
  config.grid_cols = 2;
  config.grid_rows = 1;
  config.min_tilt_deg = 15.0;
  Coverage coverage = EmptyCoverage(config);
  AddToCoverage(CoverSample(Block(10, 10, 2, 16, 16), 640, 480, config), &coverage);
  EXPECT_EQ(CoverageFeedback(coverage, config),
            "missing: row 1 col 2; tilt about x < -15 deg, tilt about y < -15 deg");
}

TEST(CoverageTest, TheBoardIsStillWhenNoCornerMovedMoreThanTheLimit) {
  const std::vector<Eigen::Vector2d> a = {{100, 100}, {200, 100}};
  EXPECT_TRUE(BoardStill(a, {{100.5, 100}, {200, 99.5}}, 1.0));
  EXPECT_FALSE(BoardStill(a, {{100, 100}, {201.5, 100}}, 1.0));
  EXPECT_FALSE(BoardStill(a, {{100, 100}}, 1.0));  // a corner lost
  EXPECT_FALSE(BoardStill({}, {}, 1.0));           // no previous frame
}

TEST(CoverageTest, ABadConfigNamesTheField) {
  CoverageConfig config;
  config.grid_cols = 0;
  try {
    config.Validate("hw.yaml", "coverage.");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("hw.yaml: coverage.grid_cols"));
  }
}

}  // namespace
}  // namespace aerograsp
