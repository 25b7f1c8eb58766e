#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/config.h"
#include "core/object_model.h"
#include "core/shape_mesh.h"
#include "core/transforms.h"
#include "detection/object_tracker.h"
#include "detection/scene_segmentation.h"
#include "hardware/sim/d435_model.h"
#include "hardware/sim/rgbd_renderer.h"
#include "rendered_frame.h"

namespace aerograsp {
namespace {

/// An object (the crawler unless named) lying on a support pipe (radius 8 cm,
/// 3 m long, across the image) in front of a floor 1.8 m away, its top facing
/// the camera: the scene the whole-frame search must not mistake (the pipe
/// explains as much depth as a crawler half buried in it).
class PipeScene {
 public:
  explicit PipeScene(const std::string& object_name = "crawler")
      : rng_(7), half_height_m_(0.5 * ObjectModel::Load(object_name).dimensions_m.z()) {
    RenderMesh floor;
    floor.mesh = MakeBoxMesh(Eigen::Vector3d(6.0, 6.0, 0.05));
    floor.material.albedo = Eigen::Vector3f(0.5f, 0.5f, 0.45f);
    for (Eigen::Vector3d& v : floor.mesh.vertices) v.z() += 1.8;  // static meshes are in c
    renderer_.AddMesh(floor, RgbdRenderer::Motion::kStatic);
    RenderMesh pipe;
    pipe.mesh = MakeCylinderMesh(0.08, 3.0, 48);
    pipe.material.albedo = Eigen::Vector3f(0.6f, 0.6f, 0.65f);
    const Eigen::Matrix3d across = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).matrix();
    for (Eigen::Vector3d& v : pipe.mesh.vertices) v = across * v + pipe_axis_c_;
    renderer_.AddMesh(pipe, RgbdRenderer::Motion::kStatic);
    RenderMesh object;
    object.mesh = ObjectModel::Load(object_name).mesh_o;
    object_id_ = renderer_.AddMesh(object);
  }
  /// The object's pose: its height (o's z) along the camera's axis, its back on the pipe.
  Eigen::Isometry3d TruthAt(int k) const {
    Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
    cMo.linear() = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                       .toRotationMatrix();
    cMo.translation() = Eigen::Vector3d(0.002 * k, 0.0, pipe_axis_c_.z() - 0.08 - half_height_m_);
    return cMo;
  }
  void Render(const Eigen::Isometry3d& cMo, ColorImage* color, DepthImage* depth) {
    renderer_.SetPose(object_id_, cMo);
    testing::RenderD435Frame(renderer_, K_, &rng_, color, depth);
  }
  const CameraIntrinsics& K() const { return K_; }

 private:
  RgbdRenderer renderer_;
  FastRandom rng_;
  double half_height_m_;
  CameraIntrinsics K_;
  Eigen::Vector3d pipe_axis_c_{0.0, 0.0, 0.86};
  int object_id_ = -1;
};

PipeScene& Scene() {
  static PipeScene scene;
  return scene;
}

TEST(SceneSegmentationTest, TheObjectOnThePipeIsTheFirstPiece) {
  const ObjectModel object = ObjectModel::Load("crawler");
  const ModelCloud model = BuildModelCloud(object.mesh_o, ModelCloudOptions{});
  ColorImage color;
  DepthImage depth;
  Scene().Render(Scene().TruthAt(0), &color, &depth);
  SceneCloudOptions cloud_options;
  cloud_options.target_points = 8000;
  const SceneCloud cloud = BuildSceneCloud(
      color, depth, 0.001, Scene().K(), PixelBox{0, 0, depth.width, depth.height}, cloud_options);
  const SceneSegments pieces =
      SegmentScene(cloud, Scene().K(), model.diameter_m, model.box_radius_m, 0.04, 0.0047,
                   SegmentationOptions{});
  // The floor and the pipe are set aside; what is left is mostly the crawler.
  EXPECT_GE(pieces.surfaces, 2);
  EXPECT_LT(pieces.foreground.points_c.size(), cloud.points_c.size() / 4);
  ASSERT_FALSE(pieces.centres_c.empty());
  EXPECT_LT((pieces.centres_c.front() - Scene().TruthAt(0).translation()).norm(), 0.03);
}

// The pipe object (9 cm across, 20 cm long) lying along the support pipe:
// itself a cylinder, but no larger than the object, so it is not set aside
// with the support pipe and the floor.
TEST(SceneSegmentationTest, ThePipeObjectOnTheSupportPipeIsNotSetAsideAsALargeCylinder) {
  const ObjectModel object = ObjectModel::Load("pipe");
  const ModelCloud model = BuildModelCloud(object.mesh_o, ModelCloudOptions{});
  PipeScene scene("pipe");
  ColorImage color;
  DepthImage depth;
  scene.Render(scene.TruthAt(0), &color, &depth);
  SceneCloudOptions cloud_options;
  cloud_options.target_points = 8000;
  const SceneCloud cloud = BuildSceneCloud(
      color, depth, 0.001, scene.K(), PixelBox{0, 0, depth.width, depth.height}, cloud_options);
  const SceneSegments pieces =
      SegmentScene(cloud, scene.K(), model.diameter_m, model.box_radius_m,
                   0.5 * object.dimensions_m.minCoeff(), 0.0047, SegmentationOptions{});
  EXPECT_GE(pieces.surfaces, 2);
  // The object's visible points all stay in the foreground.
  const Eigen::Isometry3d oMc = scene.TruthAt(0).inverse();
  const auto on_object = [&](const Eigen::Vector3f& p_c) {
    const Eigen::Vector3d p_o = oMc * p_c.cast<double>();
    return std::abs(p_o.x()) < 0.095 && std::hypot(p_o.y(), p_o.z()) > 0.035 &&
           std::hypot(p_o.y(), p_o.z()) < 0.05;
  };
  std::size_t object_points = 0, kept = 0;
  for (const Eigen::Vector3f& p : cloud.points_c) object_points += on_object(p);
  for (const Eigen::Vector3f& p : pieces.foreground.points_c) kept += on_object(p);
  ASSERT_GT(object_points, 100u);
  EXPECT_GT(kept, object_points * 9 / 10);
  ASSERT_FALSE(pieces.centres_c.empty());
  EXPECT_LT((pieces.centres_c.front() - scene.TruthAt(0).translation()).norm(), 0.03);
}

TEST(SceneSegmentationTest, TheTrackerFindsTheObjectOnThePipeWithoutADetector) {
  ObjectTracker tracker(ObjectModel::Load("crawler"), PerceptionOptions{}, nullptr);
  ColorImage color;
  DepthImage depth;
  FrameReport r;
  int k = 0;
  for (; k < 6 && r.estimate.state != TrackState::kFound; ++k) {
    Scene().Render(Scene().TruthAt(k), &color, &depth);
    r = tracker.Process(color, depth, k / 30.0, Scene().K(), 0.001);
  }
  ASSERT_EQ(r.estimate.state, TrackState::kFound);
  const Eigen::Isometry3d truth = Scene().TruthAt(k - 1);
  // The right pose (not the pipe, not a pose half buried in it), to within
  // what one face seen square-on fixes.
  EXPECT_LT(ComparePoses(truth, r.estimate.cMo).translation_m, 0.005);
  EXPECT_LT(
      SymmetricRotationError(r.estimate.cMo.linear(), truth.linear(), tracker.model().symmetry),
      5.0 * M_PI / 180);
}

TEST(SceneSegmentationTest, OptionsOutOfRangeAreRejectedByName) {
  SegmentationOptions options;
  options.surface_extent = 0.5;
  try {
    options.Validate("perception.yaml", "segment.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "perception.yaml: segment.surface_extent: must be in [1, 100] (times the "
                 "object's diameter)");
  }
}

}  // namespace
}  // namespace aerograsp
