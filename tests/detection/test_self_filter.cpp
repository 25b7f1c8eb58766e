#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/config.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "core/shape_mesh.h"
#include "detection/object_tracker.h"
#include "detection/pose_support.h"
#include "detection/self_filter.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/scene.h"
#include "rendered_frame.h"

namespace aerograsp {
namespace {

/// Joints (j0, j1, j2 on a grid, the roll 0) within the limits that put the
/// arm's tool point nearest `target_c` (m, camera frame).
Eigen::VectorXd JointsNear(const Platform& platform, Side side, const Eigen::Vector3d& target_c) {
  const ArmModel& arm = platform.arm(side);
  const Eigen::Isometry3d cMb = platform.dMc().inverse() * platform.dMb(side);
  Eigen::VectorXd best = platform.home(side), q = platform.home(side);
  double best_m = 1e9;
  constexpr int kSteps = 24;
  for (int i = 0; i <= kSteps; ++i) {
    for (int j = 0; j <= kSteps; ++j) {
      for (int k = 0; k <= kSteps; ++k) {
        const int idx[3] = {i, j, k};
        for (int n = 0; n < 3; ++n) {
          q[n] = arm.lower_limits()[n] +
                 (arm.upper_limits()[n] - arm.lower_limits()[n]) * idx[n] / kSteps;
        }
        const double m = (cMb * arm.ForwardKinematics(q).translation() - target_c).norm();
        if (m < best_m) {
          best_m = m;
          best = q;
        }
      }
    }
  }
  return best;
}

/// The 4-DoF platform's arms reaching down in front of its camera, a crawler
/// between their grippers and the ground behind, rendered with the D435 model
/// from the camera (the world frame here is the camera's).
class ArmsInView {
 public:
  ArmsInView()
      : platform_(Platform::Load(DataPath("config/platform_4dof.yaml"))),
        object_(ObjectModel::Load("crawler")),
        rng_(11) {
    RenderMesh ground;
    ground.mesh = MakeBoxMesh(Eigen::Vector3d(4.0, 4.0, 0.05));
    ground.material.albedo = Eigen::Vector3f(0.5f, 0.45f, 0.35f);
    for (Eigen::Vector3d& v : ground.mesh.vertices) v.z() += 0.9;
    ground_id_ = renderer_.AddMesh(ground, RgbdRenderer::Motion::kStatic);
    RenderMesh object;
    object.mesh = object_.mesh_o;
    object_id_ = renderer_.AddMesh(object);
    cMo_.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    cMo_.translation() = Eigen::Vector3d(0.0, 0.02, 0.45);
    renderer_.SetPose(object_id_, cMo_);
    const Eigen::Isometry3d cMd = platform_.dMc().inverse();
    for (int a = 0; a < 2; ++a) {
      const Side side = kSides[a];
      q_[a] = JointsNear(platform_, side, Eigen::Vector3d(a == 0 ? -0.07 : 0.07, 0.0, 0.36));
      std::vector<Eigen::Isometry3d> bMs;
      platform_.arm(side).SegmentPoses(q_[a], &bMs);
      const std::vector<RenderMesh> meshes = ArmRenderMeshes(platform_.arm(side));
      for (std::size_t s = 0; s < meshes.size(); ++s) {
        const int id = renderer_.AddMesh(meshes[s]);
        renderer_.SetPose(id, cMd * platform_.dMb(side) * bMs[s]);
        arm_ids_.push_back(id);
      }
    }
    testing::RenderD435Frame(renderer_, K_, &rng_, &color_, &depth_, &truth_);
  }

  bool IsArm(int u, int v) const {
    const int id = truth_.object_id.at(u, v);
    return std::find(arm_ids_.begin(), arm_ids_.end(), id) != arm_ids_.end();
  }

  Platform platform_;
  ObjectModel object_;
  FastRandom rng_;
  RgbdRenderer renderer_;
  CameraIntrinsics K_;
  Eigen::Isometry3d cMo_ = Eigen::Isometry3d::Identity();
  ArmJointPositions q_;
  int ground_id_ = -1, object_id_ = -1;
  std::vector<int> arm_ids_;
  ColorImage color_;
  DepthImage depth_;
  RenderBuffers truth_;
};

const ArmsInView& Scene() {
  static const ArmsInView scene;
  return scene;
}

constexpr double kDepthScaleM = 0.001;

/// Of the pixels with depth in `before`, those showing an arm (or not) and dropped.
struct Dropped {
  int arm = 0, arm_dropped = 0, other = 0, other_dropped = 0;
};
Dropped CountDropped(const ArmsInView& scene, const DepthImage& before, const DepthImage& after) {
  Dropped d;
  for (int v = 0; v < before.height; ++v) {
    for (int u = 0; u < before.width; ++u) {
      if (before.at(u, v) == 0) continue;
      const bool dropped = after.at(u, v) == 0;
      if (scene.IsArm(u, v)) {
        ++d.arm;
        d.arm_dropped += dropped;
      } else {
        ++d.other;
        d.other_dropped += dropped;
      }
    }
  }
  return d;
}

TEST(SelfFilterTest, DropsTheArmsPixelsOfARenderedFrameAndKeepsTheRest) {
  const ArmsInView& scene = Scene();
  const RobotSelfFilter filter(scene.platform_, SelfFilterOptions{});
  DepthImage depth = scene.depth_;
  const SelfFilterResult result =
      filter.Apply(scene.q_, scene.platform_.dMc(), scene.K_, kDepthScaleM, &depth);
  const Dropped d = CountDropped(scene, scene.depth_, depth);
  ASSERT_GT(d.arm, 5000) << "the arms must be well in view";
  EXPECT_EQ(result.dropped_pixels, d.arm_dropped + d.other_dropped);
  EXPECT_GE(d.arm_dropped, 0.98 * d.arm) << d.arm_dropped << " of " << d.arm;
  // What the margin takes besides the arms: the depth camera's smeared edges
  // and the object where the fingers touch it.
  EXPECT_LE(d.other_dropped, 0.02 * d.other) << d.other_dropped << " of " << d.other;
  // Only the shapes' boxes are tested, not the whole frame.
  EXPECT_LT(result.tested_pixels, 2 * (d.arm + d.other));
}

TEST(SelfFilterTest, ALargerMarginDropsMore) {
  const ArmsInView& scene = Scene();
  SelfFilterOptions wide;
  wide.margin_m = 0.05;
  DepthImage narrow_depth = scene.depth_, wide_depth = scene.depth_;
  const int narrow =
      RobotSelfFilter(scene.platform_, SelfFilterOptions{})
          .Apply(scene.q_, scene.platform_.dMc(), scene.K_, kDepthScaleM, &narrow_depth)
          .dropped_pixels;
  const int more = RobotSelfFilter(scene.platform_, wide)
                       .Apply(scene.q_, scene.platform_.dMc(), scene.K_, kDepthScaleM, &wide_depth)
                       .dropped_pixels;
  EXPECT_GT(more, narrow + 1000);
}

TEST(SelfFilterTest, AnArmWithoutValidJointsIsLeftOut) {
  const ArmsInView& scene = Scene();
  const RobotSelfFilter filter(scene.platform_, SelfFilterOptions{});
  ArmJointPositions q = scene.q_;
  q[0] = Eigen::VectorXd::Zero(2);                     // the wrong size
  q[1][1] = std::numeric_limits<double>::quiet_NaN();  // not finite
  DepthImage depth = scene.depth_;
  const SelfFilterResult result =
      filter.Apply(q, scene.platform_.dMc(), scene.K_, kDepthScaleM, &depth);
  EXPECT_EQ(result.dropped_pixels, 0);
  EXPECT_EQ(result.shapes, 0);
  EXPECT_TRUE(depth == scene.depth_);
}

TEST(SelfFilterTest, AMarginOutOfRangeIsRefusedByName) {
  SelfFilterOptions options;
  options.margin_m = 0.2;
  try {
    options.Validate("perception.yaml", "self_filter.");
    FAIL() << "a 0.2 m margin was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("perception.yaml: self_filter.margin_m"),
              std::string::npos)
        << e.what();
  }
}

TEST(ArmJointHistoryTest, ReadsTheJointsBetweenSamplesAndHoldsThemOutside) {
  ArmJointHistory history(1.0);
  EXPECT_FALSE(history.At(0.0).has_value());
  history.Add(1.0, {Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(2.0, 2.0)});
  history.Add(1.1, {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(2.0, 4.0)});
  const ArmJointPositions mid = *history.At(1.025);
  EXPECT_NEAR(mid[0][0], 0.25, 1e-9);
  EXPECT_NEAR(mid[1][1], 2.5, 1e-9);
  EXPECT_NEAR((*history.At(0.5))[0][0], 0.0, 1e-12);
  EXPECT_NEAR((*history.At(2.0))[1][1], 4.0, 1e-12);
}

TEST(ArmJointHistoryTest, ForgetsSamplesOlderThanItKeeps) {
  ArmJointHistory history(0.5);
  for (int k = 0; k <= 100; ++k)
    history.Add(0.01 * k, {Eigen::VectorXd::Constant(1, k), Eigen::VectorXd::Constant(1, k)});
  // 0.2 s is gone: the oldest kept sample (about 0.5 s back) stands for it.
  EXPECT_GE((*history.At(0.2))[0][0], 49.0);
  EXPECT_NEAR((*history.At(0.755))[0][0], 75.5, 1e-9);
}

TEST(ObjectTrackerSelfFilterTest, TheObjectUnderTheFingersCountsAsHiddenNotAsMissing) {
  const ArmsInView& scene = Scene();
  // The tracker's support check at the true pose, without and with the arms' joints.
  FrameReport reports[2];
  for (int with = 0; with < 2; ++with) {
    ObjectTracker tracker(scene.object_, PerceptionOptions{}, nullptr);
    tracker.SetRobot(scene.platform_);
    tracker.SetInitialPose(scene.cMo_);
    reports[with] =
        tracker.Process(scene.color_, scene.depth_, 0.0, scene.K_, kDepthScaleM, std::nullopt,
                        with ? std::optional<ArmJointPositions>(scene.q_) : std::nullopt);
  }
  EXPECT_EQ(reports[0].self_filter.dropped_pixels, 0);
  EXPECT_GT(reports[1].self_filter.dropped_pixels, 5000);
  ASSERT_TRUE(reports[1].icp.ok);
  EXPECT_GT(reports[1].support.coverage(), reports[0].support.coverage() + 0.05)
      << reports[1].support.coverage() << " against " << reports[0].support.coverage();
  const double error_m = (reports[1].icp.cMo.translation() - scene.cMo_.translation()).norm();
  EXPECT_LT(error_m, 0.005);
  // At the true pose the model behind the fingers is hidden, so the support
  // passes the tracker's test (ICP's few millimetres off it move the
  // silhouette's points onto the background, which decides the frame's flag).
  DepthImage dropped = scene.depth_;
  RobotSelfFilter(scene.platform_, SelfFilterOptions{})
      .Apply(scene.q_, scene.platform_.dMc(), scene.K_, kDepthScaleM, &dropped);
  const ObjectTracker tracker(scene.object_, PerceptionOptions{}, nullptr);
  const PoseSupport at_truth =
      ScorePoseSupport(tracker.model(), scene.cMo_, scene.color_, dropped, kDepthScaleM, scene.K_);
  EXPECT_GE(at_truth.ratio(), PerceptionOptions{}.min_support_ratio);
  EXPECT_GT(at_truth.coverage(), 0.9);
}

// Kept in the depth (drop_from_depth false), the arms' pixels still feed the
// cloud and ICP as without the filter, and only the support check takes the
// object behind them as hidden: nearly all of the visible model is explained
// (0.4 without the joints).
TEST(ObjectTrackerSelfFilterTest, ArmsKeptInTheDepthOnlyHideTheObjectFromTheSupportCheck) {
  const ArmsInView& scene = Scene();
  // Without the joints, with them dropped, with them kept in the depth.
  FrameReport reports[3];
  for (int k = 0; k < 3; ++k) {
    PerceptionOptions options;
    options.self_filter.drop_from_depth = k != 2;
    ObjectTracker tracker(scene.object_, options, nullptr);
    tracker.SetRobot(scene.platform_);
    tracker.SetInitialPose(scene.cMo_);
    reports[k] =
        tracker.Process(scene.color_, scene.depth_, 0.0, scene.K_, kDepthScaleM, std::nullopt,
                        k ? std::optional<ArmJointPositions>(scene.q_) : std::nullopt);
  }
  ASSERT_TRUE(reports[2].measured);
  EXPECT_GT(reports[2].self_filter.dropped_pixels, 5000);
  EXPECT_EQ(reports[2].cloud_points, reports[0].cloud_points);
  EXPECT_GT(reports[2].support.coverage(), 0.85) << reports[1].support.coverage();
  EXPECT_GT(reports[2].support.coverage(), reports[0].support.coverage() + 0.05);
}

// Out of the cloud only (drop_from_cloud), the arms' pixels no longer reach
// ICP (the cloud of the crop is smaller by them), and the support check still
// takes the object behind them as hidden.
TEST(ObjectTrackerSelfFilterTest, ArmsOutOfTheCloudOnlyLeaveTheSupportCheckAsKeptInTheDepth) {
  const ArmsInView& scene = Scene();
  // Kept in the depth, then out of the cloud only.
  FrameReport reports[2];
  for (int k = 0; k < 2; ++k) {
    PerceptionOptions options;
    options.self_filter.drop_from_depth = false;
    options.self_filter.drop_from_cloud = k == 1;
    options.cloud.target_points = 100000;  // every pixel of the crop: the counts compare
    ObjectTracker tracker(scene.object_, options, nullptr);
    tracker.SetRobot(scene.platform_);
    tracker.SetInitialPose(scene.cMo_);
    reports[k] = tracker.Process(scene.color_, scene.depth_, 0.0, scene.K_, kDepthScaleM,
                                 std::nullopt, std::optional<ArmJointPositions>(scene.q_));
  }
  ASSERT_TRUE(reports[1].measured);
  EXPECT_LT(reports[1].cloud_points, reports[0].cloud_points);
  EXPECT_GT(reports[1].support.coverage(), 0.85);
  const double error_m = (reports[1].icp.cMo.translation() - scene.cMo_.translation()).norm();
  EXPECT_LT(error_m, 0.005);
}

}  // namespace
}  // namespace aerograsp
