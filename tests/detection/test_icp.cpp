#include <gtest/gtest.h>

#include <algorithm>

#include "core/data_dir.h"
#include "core/transforms.h"
#include "detection/icp.h"
#include "detection/pose_support.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/world.h"
#include "test_helpers.h"

namespace aerograsp {
namespace {
using testing::CrawlerModel;
using testing::Perturbed;
using testing::PlainCrawlerModel;
using testing::TypicalCMo;
using testing::VisibleScene;

const Eigen::Vector3f kUp(0, 0, 1), kYellow(230, 180, 20), kGrey(40, 40, 40);

TEST(IcpRejectorTest, DistanceRejectsFarPairsOnly) {
  RejectorThresholds t;
  t.max_distance_m = 0.01;
  EXPECT_EQ(ClassifyPair({0, 0, 0.009f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0, 0, 0.011f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kDistance);
}

TEST(IcpRejectorTest, DistanceAlongThePixelRayAllowsTheDepthNoise) {
  RejectorThresholds t;
  t.max_distance_m = 0.008;
  t.ray = Eigen::Vector3f::UnitZ();
  t.max_along_ray_m = 0.03;
  EXPECT_EQ(ClassifyPair({0, 0, 0.029f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0, 0, -0.029f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0, 0, 0.031f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kDistance);
  EXPECT_EQ(ClassifyPair({0.007f, 0, 0.02f}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0.009f, 0, 0}, kUp, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kDistance);
}

TEST(IcpRejectorTest, NormalRejectsDisagreeingNormalsOnly) {
  RejectorThresholds t;
  t.min_normal_cos = 0.7;  // 45.6 deg
  const Eigen::Vector3f tilted40 = Eigen::AngleAxisf(0.70f, Eigen::Vector3f::UnitX()) * kUp;
  const Eigen::Vector3f tilted50 = Eigen::AngleAxisf(0.87f, Eigen::Vector3f::UnitX()) * kUp;
  EXPECT_EQ(ClassifyPair({0, 0, 0}, tilted40, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0, 0, 0}, tilted50, kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNormal);
  // A scene normal that could not be fitted (zero) is not judged.
  EXPECT_EQ(ClassifyPair({0, 0, 0}, Eigen::Vector3f::Zero(), kYellow, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  t.min_normal_cos = -1.0;  // disabled
  EXPECT_EQ(ClassifyPair({0, 0, 0}, -kUp, kYellow, {0, 0, 0}, kUp, kYellow, t), Rejection::kNone);
}

TEST(IcpRejectorTest, ColorRejectsOtherHuesButNotShading) {
  RejectorThresholds t;
  t.max_color_distance = 150;
  // The same yellow at half the light is the same colour.
  EXPECT_EQ(ClassifyPair({0, 0, 0}, kUp, kYellow * 0.5f, {0, 0, 0}, kUp, kYellow, t),
            Rejection::kNone);
  EXPECT_EQ(ClassifyPair({0, 0, 0}, kUp, kGrey, {0, 0, 0}, kUp, kYellow, t), Rejection::kColor);
  EXPECT_GT(ColorDistance(kGrey, kYellow), 150.0f);
  EXPECT_NEAR(ColorDistance(kYellow, kYellow * 0.3f), 0.0f, 1e-3f);
  t.max_color_distance = 768;  // disabled
  EXPECT_EQ(ClassifyPair({0, 0, 0}, kUp, kGrey, {0, 0, 0}, kUp, kYellow, t), Rejection::kNone);
}

TEST(IcpRejectorTest, ColorDistanceIsTheL1OfBrightnessNormalizedColours) {
  // A caller normalising one colour once gets the same float as ColorDistance.
  const Eigen::Vector3f black(0, 0, 0), dim(0.2f, 0.3f, 0.1f), shaded = kYellow * 0.3f;
  for (const Eigen::Vector3f& a : {kGrey, kYellow, black, dim}) {
    for (const Eigen::Vector3f& b : {kGrey, shaded, black, dim}) {
      EXPECT_EQ(ColorDistance(a, b),
                (BrightnessNormalized(a) - BrightnessNormalized(b)).cwiseAbs().sum());
    }
  }
  EXPECT_FLOAT_EQ(BrightnessNormalized(kYellow).sum(), 384.0f);
  EXPECT_EQ(BrightnessNormalized(dim), dim * 384.0f);  // a sum below 1 counts as 1
}

TEST(IcpRejectorTest, EachRejectorIsAppliedInOrder) {
  RejectorThresholds t;
  // Fails all three: reported as distance (Eq. 1 first).
  EXPECT_EQ(ClassifyPair({0, 0, 1}, -kUp, kGrey, {0, 0, 0}, kUp, kYellow, t), Rejection::kDistance);
  // Fails normal and colour: normal (Eq. 2 before Eq. 3).
  EXPECT_EQ(ClassifyPair({0, 0, 0}, -kUp, kGrey, {0, 0, 0}, kUp, kYellow, t), Rejection::kNormal);
}

TEST(IcpTest, ConvergesFromAPerturbedPose) {
  const ModelCloud& model = CrawlerModel();
  const Eigen::Isometry3d truth = TypicalCMo();
  const SceneCloud scene = VisibleScene(model, truth);
  const IcpResult r =
      RefinePoseIcp(model, scene, Perturbed(truth, {0.01, -0.008, 0.006}, {0.05, -0.04, 0.06}));
  ASSERT_TRUE(r.ok);
  const PoseError e = ComparePoses(truth, r.cMo);
  EXPECT_LT(e.translation_m, 0.001);
  EXPECT_LT(e.rotation_rad, 0.2 * M_PI / 180);
  EXPECT_GT(r.inlier_ratio, 0.95);
  EXPECT_LE(r.rejected_color, r.scene_points / 100);  // only at colour seams
}

// A plain mesh (no vertex colours) against the textured object's points: the
// model has no colour to compare, so Eq. 3 rejects nothing and ICP converges on
// geometry alone.
TEST(IcpTest, APlainMeshIsPairedOnGeometryAgainstATexturedScene) {
  const ModelCloud& plain = PlainCrawlerModel();
  ASSERT_FALSE(plain.has_colors());
  ASSERT_TRUE(CrawlerModel().has_colors());
  const Eigen::Isometry3d truth = TypicalCMo();
  const SceneCloud scene = VisibleScene(CrawlerModel(), truth);  // the real, coloured surface
  const IcpResult r =
      RefinePoseIcp(plain, scene, Perturbed(truth, {0.01, -0.008, 0.006}, {0.05, -0.04, 0.06}));
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.rejected_color, 0);
  EXPECT_GT(r.inlier_ratio, 0.95);
  EXPECT_LT(ComparePoses(truth, r.cMo).translation_m, 0.001);
}

// A slab of the wrong colour hugging the yellow body 4 mm above it, with the
// body's normals: only the colour rejector can tell it from the object. With the
// rejector it counts the slab's pairs and the pose stays put; disabled, the slab
// drags the pose towards itself.
TEST(IcpTest, ColorRejectorRunsAndRemovesAWrongColouredSurface) {
  const ModelCloud& model = CrawlerModel();
  const Eigen::Isometry3d truth = TypicalCMo();
  SceneCloud scene = VisibleScene(model, truth);
  const Eigen::Isometry3f T = truth.cast<float>();
  int slab = 0;
  for (std::size_t i = 0; i < model.points_o.size(); ++i) {
    const Eigen::Vector3f& p = model.points_o[i];
    if (model.normals_o[i].z() > 0.9f && std::abs(p.y()) < 0.045f && model.colors[i].x() > 200) {
      scene.points_c.push_back(T * (p + Eigen::Vector3f(0, 0, 0.004f)));
      scene.normals_c.push_back(T.linear() * model.normals_o[i]);
      scene.colors.push_back(Eigen::Vector3f(30, 60, 220));  // blue
      ++slab;
    }
  }
  ASSERT_GT(slab, 100);
  const Eigen::Isometry3d start = Perturbed(truth, {0.003, 0.0, 0.0}, {0.0, 0.02, 0.0});
  IcpOptions with;
  const IcpResult r_with = RefinePoseIcp(model, scene, start, with);
  IcpOptions without = with;
  without.max_color_distance = 768.0;
  const IcpResult r_without = RefinePoseIcp(model, scene, start, without);
  ASSERT_TRUE(r_with.ok);
  ASSERT_TRUE(r_without.ok);
  // Most pairs reach the colour test; the slab's points seen most obliquely are
  // more than Eq. 1's last 8 mm from the body along their rays, or their rays
  // meet a track's side (Eq. 2).
  EXPECT_GE(r_with.rejected_color, slab * 7 / 10);
  EXPECT_EQ(r_without.rejected_color, 0);
  EXPECT_LT(ComparePoses(truth, r_with.cMo).translation_m, 0.001);
  EXPECT_GT(ComparePoses(truth, r_without.cMo).translation_m, 0.0015);
}

struct TruthAndIcp {
  Eigen::Isometry3d truth;  ///< cMo
  IcpResult icp;
};

/// ICP started at the truth on `frames` simulated frames 0.2 s apart of the
/// world `config` (seed 7), on the crop around the true pose.
std::vector<TruthAndIcp> IcpFromTheTruth(const ModelCloud& model, const WorldConfig& config,
                                         int frames) {
  World world(config, 7);
  SimCamera camera(&world);
  RgbdFrame frame;
  std::vector<TruthAndIcp> out;
  for (int k = 0; k < frames; ++k) {
    world.StepTo(0.2 * k);
    if (!camera.Grab(&frame)) break;
    const Eigen::Isometry3d truth = world.wMc().inverse() * world.wMo();
    const PoseSupport support = ScorePoseSupport(model, truth, frame.color, frame.depth,
                                                 camera.depth_scale_m(), camera.intrinsics());
    const SceneCloud scene = BuildSceneCloud(frame.color, frame.depth, camera.depth_scale_m(),
                                             camera.intrinsics(), support.box.Grown(0.15));
    out.push_back({truth, RefinePoseIcp(model, scene, truth)});
  }
  return out;
}

// The simulator's crawler on its pipe 1.5 m away (world_distance_1.5m.yaml),
// where the D435's depth noise is 10 mm: paired with the nearest model point,
// noisy points near the edges and on the pipe pulled ICP started at the truth
// into a roll of 3.6 deg about the long axis, on average over the frames.
TEST(IcpTest, DepthNoiseAlongTheRaysDoesNotTiltThePose) {
  const int frames = 6;
  const std::vector<TruthAndIcp> runs = IcpFromTheTruth(
      CrawlerModel(), WorldConfig::Load(DataPath("config/world_distance_1.5m.yaml")), frames);
  ASSERT_EQ(runs.size(), frames);
  double roll_sum_rad = 0.0;
  for (const TruthAndIcp& run : runs) {
    ASSERT_TRUE(run.icp.ok);
    const Eigen::AngleAxisd error(run.truth.linear().transpose() * run.icp.cMo.linear());
    roll_sum_rad += (error.axis() * error.angle()).x();
    EXPECT_LT(error.angle() * 180.0 / M_PI, 2.0);
  }
  EXPECT_LT(std::abs(roll_sum_rad / frames) * 180.0 / M_PI, 1.0);
}

// The pipe (a 6 mm wall around a hollow) 1.5 m away, where the depth noise is
// 10.6 mm: a point the noise pushed more than the wall's thickness behind the
// near surface lies nearest the inner wall, whose normal faces away from the
// camera, and the normal rejector dropped it; the points pushed nearer all
// stayed, and ICP started at the truth settled 8 mm nearer the camera.
TEST(IcpTest, DepthNoiseBehindAThinWallDoesNotPullThePoseNearer) {
  WorldConfig config = WorldConfig::Load(DataPath("config/world_distance_1.5m.yaml"));
  config.object.name = "pipe";
  const int frames = 6;
  const std::vector<TruthAndIcp> runs =
      IcpFromTheTruth(BuildModelCloud(ObjectModel::Load("pipe").mesh_o), config, frames);
  ASSERT_EQ(runs.size(), frames);
  double depth_error_sum_m = 0.0;
  for (const TruthAndIcp& run : runs) {
    ASSERT_TRUE(run.icp.ok);
    const Eigen::Vector3d ray = run.truth.translation().normalized();
    depth_error_sum_m += (run.icp.cMo.translation() - run.truth.translation()).dot(ray);
  }
  EXPECT_LT(std::abs(depth_error_sum_m / frames), 0.002)
      << "mean error along the ray " << depth_error_sum_m / frames;
}

// Points on the surface whose normals are turned 90 deg (a bristle of wrong
// normals): the normal rejector counts them.
TEST(IcpTest, NormalRejectorRunsOnWrongNormals) {
  const ModelCloud& model = CrawlerModel();
  const Eigen::Isometry3d truth = TypicalCMo();
  SceneCloud scene = VisibleScene(model, truth);
  const std::size_t n = scene.points_c.size();
  for (std::size_t i = 0; i < n; i += 4) {
    const Eigen::Vector3f& normal = scene.normals_c[i];
    scene.normals_c[i] = normal.unitOrthogonal();
  }
  IcpOptions options;
  const IcpResult r = RefinePoseIcp(model, scene, truth, options);
  ASSERT_TRUE(r.ok);
  EXPECT_GE(r.rejected_normal, static_cast<int>(n / 4) * 9 / 10);
  options.min_normal_cos = -1.0;
  EXPECT_EQ(RefinePoseIcp(model, scene, truth, options).rejected_normal, 0);
}

// Background points 3 cm behind the object (the support pipe, the ground).
TEST(IcpTest, DistanceRejectorRunsOnBackground) {
  const ModelCloud& model = CrawlerModel();
  const Eigen::Isometry3d truth = TypicalCMo();
  SceneCloud scene = VisibleScene(model, truth);
  const std::size_t n = scene.points_c.size();
  for (std::size_t i = 0; i < n; i += 2) {
    scene.points_c.push_back(scene.points_c[i] * 1.045f);  // along the ray, ~3 cm behind
    scene.normals_c.push_back(scene.normals_c[i]);
    scene.colors.push_back(scene.colors[i]);
  }
  const int background = static_cast<int>(scene.points_c.size() - n);
  // Some land on the object's own surface: within the last iteration's Eq. 1
  // distance of a model point whose normal agrees (mostly the yellow body,
  // 0.015 m below the tracks' tops), where no geometric rejector can tell them
  // from the object. Counted at the true pose, as the ICP associates them.
  const IcpOptions options;
  const Eigen::Isometry3f oMc = truth.inverse().cast<float>();
  int on_surface = 0;
  for (std::size_t i = n; i < scene.points_c.size(); ++i) {
    const Eigen::Vector3f p = oMc * scene.points_c[i];
    const int j = model.Nearest(p);
    const double z = scene.points_c[i].z();
    const double max_distance =
        std::max(options.end_distance_m, 3.0 * options.depth_noise_per_m2 * z * z);
    on_surface +=
        j >= 0 && (model.points_o[j] - p).norm() <= max_distance &&
        model.normals_o[j].dot(oMc.linear() * scene.normals_c[i]) >= options.min_normal_cos;
  }
  ASSERT_LT(on_surface, background / 5);
  const IcpResult r =
      RefinePoseIcp(model, scene, Perturbed(truth, {0.004, 0, 0}, {0, 0, 0.03}), options);
  ASSERT_TRUE(r.ok);
  // Behind the front faces some land near the object's inner faces, where the
  // normals (Eq. 2) catch them; the rest is too far (Eq. 1): all but 1 % of
  // those off the object's surface.
  EXPECT_GT(r.rejected_distance + r.rejected_no_model, background * 4 / 10);
  EXPECT_GE(r.rejected_distance + r.rejected_no_model + r.rejected_normal,
            (background - on_surface) * 99 / 100)
      << background << " background points, " << on_surface << " on the object's surface";
  EXPECT_LT(ComparePoses(truth, r.cMo).translation_m, 0.0015);
}

TEST(IcpTest, EmptyOrTinySceneFailsWithoutThrowing) {
  const ModelCloud& model = CrawlerModel();
  EXPECT_FALSE(RefinePoseIcp(model, SceneCloud{}, TypicalCMo()).ok);
  SceneCloud few = VisibleScene(model, TypicalCMo(), 400);
  EXPECT_LT(few.points_c.size(), 30u);
  EXPECT_FALSE(RefinePoseIcp(model, few, TypicalCMo()).ok);
  Eigen::Isometry3d nan_pose = TypicalCMo();
  nan_pose.translation().x() = std::nan("");
  EXPECT_FALSE(RefinePoseIcp(model, VisibleScene(model, TypicalCMo()), nan_pose).ok);
}

}  // namespace
}  // namespace aerograsp
