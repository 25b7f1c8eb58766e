#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "mission/object_motion.h"

namespace aerograsp {
namespace {

// An object crawling at 3 cm/s along a world axis while the frames' positions
// sway +-5 mm across it and +-3 mm along it.
std::vector<StampedPosition> Crawl(const Eigen::Vector3d& axis_w, int frames) {
  std::vector<StampedPosition> positions;
  const Eigen::Vector3d across = axis_w.unitOrthogonal();
  for (int k = 0; k < frames; ++k) {
    const double t = 10.0 + k / 30.0;
    const double sway = std::sin(2.0 * M_PI * 0.5 * t);
    positions.push_back({t, Eigen::Vector3d(1.0, -2.0, 0.5) + (0.03 * t + 0.003 * sway) * axis_w +
                                0.005 * sway * across});
  }
  return positions;
}

TEST(ObjectMotionTest, FitsTheSpeedAlongTheAxisThroughTheSway) {
  const Eigen::Vector3d axis_w = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  const std::vector<StampedPosition> positions = Crawl(axis_w, 90);  // 3 s
  const std::optional<AxisMotion> m = FitAxisMotion(positions, 2.0 * axis_w, 10);
  ASSERT_TRUE(m.has_value());
  EXPECT_NEAR(m->axis_w.norm(), 1.0, 1e-12);
  EXPECT_NEAR(m->v_mps, 0.03, 0.003);
  EXPECT_DOUBLE_EQ(m->t0_s, positions.back().stamp_s);
  // Two seconds on, along the axis, within a few mm of where the crawl is.
  const double t = m->t0_s + 2.0;
  const double s_true = axis_w.dot(Eigen::Vector3d(1.0, -2.0, 0.5)) + 0.03 * t;
  EXPECT_NEAR(m->At(t), s_true, 0.006);
}

TEST(ObjectMotionTest, ConstrainReplacesOnlyTheComponentAlongTheAxis) {
  AxisMotion m;
  m.axis_w = Eigen::Vector3d::UnitY();
  m.t0_s = 1.0;
  m.s0_m = 0.2;
  m.v_mps = -0.05;
  const Eigen::Vector3d p = m.Constrain(Eigen::Vector3d(0.4, 0.9, -1.1), 3.0);
  EXPECT_DOUBLE_EQ(p.x(), 0.4);
  EXPECT_NEAR(p.y(), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(p.z(), -1.1);
}

TEST(ObjectMotionTest, TooFewFramesOrOneInstantFitNothing) {
  const Eigen::Vector3d axis_w = Eigen::Vector3d::UnitX();
  EXPECT_FALSE(FitAxisMotion(Crawl(axis_w, 5), axis_w, 10).has_value());
  EXPECT_FALSE(FitAxisMotion({}, axis_w, 0).has_value());
  std::vector<StampedPosition> same_time(12, StampedPosition{2.0, Eigen::Vector3d::Zero()});
  EXPECT_FALSE(FitAxisMotion(same_time, axis_w, 10).has_value());
  EXPECT_FALSE(FitAxisMotion(Crawl(axis_w, 30), Eigen::Vector3d::Zero(), 10).has_value());
}

TEST(ObjectMotionTest, AStillObjectFitsNoSpeed) {
  std::vector<StampedPosition> still;
  for (int k = 0; k < 60; ++k)
    still.push_back({k / 30.0, Eigen::Vector3d(0.3, 0.1, 2.0) +
                                   0.002 * std::cos(k) * Eigen::Vector3d::UnitX()});
  const std::optional<AxisMotion> m = FitAxisMotion(still, Eigen::Vector3d::UnitX(), 10);
  ASSERT_TRUE(m.has_value());
  EXPECT_NEAR(m->v_mps, 0.0, 0.002);
  EXPECT_NEAR(m->At(m->t0_s + 5.0), 0.3, 0.012);
}

// The crawl of 3 cm/s that turns back at turn_s (the end of its travel).
StampedPosition TurningCrawl(double t_s, double turn_s) {
  const double s = t_s <= turn_s ? 0.03 * t_s : 0.03 * (2.0 * turn_s - t_s);
  return {t_s, Eigen::Vector3d(s, 0.4, -0.2)};
}

LengthFitOptions Options() {
  LengthFitOptions o;
  o.window_s = 3.0;
  o.lock_min_frames = 45;
  o.refit_min_frames = 8;
  o.break_m = 0.02;
  o.break_frames = 3;
  return o;
}

TEST(LengthMotionTest, LocksOnlyWithEnoughFrames) {
  LengthMotion length(Options());
  for (int k = 0; k < 30; ++k) length.Add(TurningCrawl(k / 30.0, 100.0));
  EXPECT_FALSE(length.Lock(Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(length.motion().has_value());
  for (int k = 30; k < 90; ++k) length.Add(TurningCrawl(k / 30.0, 100.0));
  ASSERT_TRUE(length.Lock(Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(length.motion()->v_mps, 0.03, 1e-9);
}

TEST(LengthMotionTest, FollowsATurnFromTheFramesAfterIt) {
  LengthMotion length(Options());
  double t = 0.0;
  for (; t < 3.0; t += 1.0 / 30.0) length.Add(TurningCrawl(t, 3.5));
  ASSERT_TRUE(length.Lock(Eigen::Vector3d::UnitX()));
  // Then a frame now and then (the arms hide the ends), through the turn.
  for (; t < 5.0; t += 0.1) length.Add(TurningCrawl(t, 3.5));
  EXPECT_EQ(length.breaks(), 1);
  EXPECT_NEAR(length.motion()->v_mps, -0.03, 1e-6);
  EXPECT_NEAR(length.motion()->At(t + 0.5), TurningCrawl(t + 0.5, 3.5).p_w.x(), 1e-6);
}

TEST(LengthMotionTest, StandsStillUntilTheNewMotionHasFrames) {
  LengthMotion length(Options());
  double t = 0.0;
  for (; t < 3.0; t += 1.0 / 30.0) length.Add(TurningCrawl(t, 100.0));
  ASSERT_TRUE(length.Lock(Eigen::Vector3d::UnitX()));
  // Three frames 0.12 m ahead of the fit start a new one, standing still.
  for (int k = 0; k < 3; ++k) length.Add({t + 3.0 + k / 30.0, Eigen::Vector3d(0.30, 0.0, 0.0)});
  EXPECT_EQ(length.breaks(), 1);
  EXPECT_DOUBLE_EQ(length.motion()->v_mps, 0.0);
  EXPECT_NEAR(length.motion()->At(t + 10.0), 0.30, 1e-12);
}

TEST(LengthMotionTest, SetsASingleStrayFrameAside) {
  LengthMotion length(Options());
  double t = 0.0;
  for (; t < 3.0; t += 1.0 / 30.0) length.Add(TurningCrawl(t, 100.0));
  ASSERT_TRUE(length.Lock(Eigen::Vector3d::UnitX()));
  length.Add({t, Eigen::Vector3d(0.5, 0.0, 0.0)});  // 0.41 m off: the tracker slid
  length.Add(TurningCrawl(t + 0.1, 100.0));
  EXPECT_EQ(length.breaks(), 0);
  EXPECT_NEAR(length.motion()->v_mps, 0.03, 1e-9);
  EXPECT_NEAR(length.motion()->At(t + 1.0), 0.03 * (t + 1.0), 1e-9);
}

TEST(LengthMotionTest, ResetForgetsFramesAndFit) {
  LengthMotion length(Options());
  for (int k = 0; k < 90; ++k) length.Add(TurningCrawl(k / 30.0, 100.0));
  ASSERT_TRUE(length.Lock(Eigen::Vector3d::UnitX()));
  length.Reset();
  EXPECT_FALSE(length.motion().has_value());
  EXPECT_EQ(length.frames(), 0u);
  EXPECT_FALSE(length.Lock(Eigen::Vector3d::UnitX()));
}

TEST(EmptyCloseShiftTest, PutsTheNearerEndAtTheTool) {
  EXPECT_NEAR(EmptyCloseShiftM(0.098, -0.11, 0.11, 0.05), -0.012, 1e-12);
  EXPECT_NEAR(EmptyCloseShiftM(-0.08, -0.11, 0.11, 0.05), 0.03, 1e-12);
}

TEST(EmptyCloseShiftTest, NoShiftFarInsideOrOutsideTheEnds) {
  EXPECT_EQ(EmptyCloseShiftM(0.05, -0.11, 0.11, 0.05), 0.0);   // 60 mm inside
  EXPECT_EQ(EmptyCloseShiftM(0.12, -0.11, 0.11, 0.05), 0.0);   // past the end already
  EXPECT_EQ(EmptyCloseShiftM(-0.11, -0.11, 0.11, 0.05), 0.0);  // at the end
  EXPECT_EQ(EmptyCloseShiftM(0.098, -0.11, 0.11, 0.0), 0.0);   // off
}

}  // namespace
}  // namespace aerograsp
