#include "app/commands/dataset_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <climits>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "app/cli_checks.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "core/platform.h"
#include "core/random.h"
#include "core/shape_mesh.h"
#include "core/transforms.h"
#include "detection/box_detector.h"
#include "detection/model_cloud.h"
#include "detection/pose_support.h"
#include "hardware/sim/d435_model.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/scene.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr int kImagesPerScene = 200;  // a new static scene (clutter, ground) every so many images
constexpr int kOccluders = 3;
constexpr int kDistractors = 2;

Eigen::Matrix3d RandomRotation(FastRandom* rng) {
  Eigen::Quaterniond q(rng->Normal(), rng->Normal(), rng->Normal(), rng->Normal());
  return q.normalized().toRotationMatrix();
}

/// wRc with the optical axis z along dir_w, image y as close to world down (+z, NED) as possible.
Eigen::Matrix3d LookAlong(const Eigen::Vector3d& dir_w) {
  const Eigen::Vector3d z = dir_w.normalized();
  Eigen::Vector3d down(0, 0, 1);
  Eigen::Vector3d y = down - down.dot(z) * z;
  if (y.norm() < 1e-3) y = Eigen::Vector3d(1, 0, 0) - z.x() * z;
  y.normalize();
  Eigen::Matrix3d R;
  R.col(0) = y.cross(z);
  R.col(1) = y;
  R.col(2) = z;
  return R;
}

/// wMc with the optical axis towards `target_w` from `distance` along `to_camera_w` (unit), the
/// target at pixel (u, v), and the image rolled by `roll` about the axis.
Eigen::Isometry3d CameraLookingAt(const Eigen::Vector3d& target_w,
                                  const Eigen::Vector3d& to_camera_w, double distance,
                                  const CameraIntrinsics& K, double u, double v, double roll) {
  Eigen::Isometry3d wMc = Eigen::Isometry3d::Identity();
  wMc.translation() = target_w + distance * to_camera_w;
  const Eigen::Vector3d d_c = K.Unproject(u, v, 1.0).normalized();
  const Eigen::Matrix3d Q =
      Eigen::Quaterniond::FromTwoVectors(d_c, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  wMc.linear() = LookAlong(-to_camera_w) *
                 Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * Q;
  return wMc;
}

RenderMesh Tinted(const RenderMesh& mesh, FastRandom* rng) {
  RenderMesh m = mesh;
  for (int c = 0; c < 3; ++c) m.material.albedo[c] = static_cast<float>(rng->Uniform(0.8, 1.15));
  return m;
}

}  // namespace

void RunDatasetCommand(const DatasetCommandOptions& options, std::ostream& out,
                       std::ostream& progress) {
  if (options.count < 1) throw std::invalid_argument("--count: must be at least 1");
  if (!(options.on_support >= 0.0 && options.on_support <= 1.0)) {
    throw std::invalid_argument("--on-support: must be in [0, 1]");
  }
  const ObjectModel object = ObjectModel::Load(options.object);
  ReportFolder folder(options.out_dir, options.overwrite, "labels.csv");
  const fs::path dir(folder.path());
  fs::create_directories(dir / "images");
  std::ofstream labels(dir / "labels.csv");
  if (!labels) throw std::runtime_error((dir / "labels.csv").string() + ": cannot be written");
  labels << "index,visible,x0,y0,x1,y1,object_pixels,coverage\n";

  const WorldConfig world = WorldConfig::Load(DataPath("config/world_default.yaml"));
  const CameraIntrinsics K;  // the D435 colour stream at 640x480 (docs/hardware.md)
  // Distractors: the other shipped objects.
  std::vector<RenderMesh> distractor_meshes;
  for (const std::string& name : ShippedObjectNames()) {
    if (name == object.name) continue;
    RenderMesh m;
    m.mesh = ObjectModel::Load(name).mesh_o;
    distractor_meshes.push_back(m);
  }
  RenderMesh object_mesh;
  object_mesh.mesh = object.mesh_o;
  // The coverage column: the visibility test of `replay` (depth only: no colour image is given),
  // for a trainer to leave out mostly hidden objects.
  const ModelCloud model_cloud = BuildModelCloud(object.mesh_o);
  // --on-support: the vehicle's arms, rendered as the simulator renders them (world.cpp).
  const bool with_support_views = options.on_support > 0.0;
  const Platform platform = Platform::Load(world.platform);
  const std::vector<RenderMesh> arm_meshes[2] = {ArmRenderMeshes(platform.arm(Side::kLeft)),
                                                 ArmRenderMeshes(platform.arm(Side::kRight))};
  const double object_half_height = 0.5 * object.dimensions_m.z();  // o: z up, as ObjectOnPipe

  FastRandom rng(options.seed * 0x9E3779B97F4A7C15ull + 17);
  std::unique_ptr<RgbdRenderer> renderer;
  int object_id = -1;
  std::vector<int> occluder_ids, distractor_ids, arm_ids[2];
  SceneConfig scene = world.scene;
  RenderBuffers truth;
  RgbdFrame frame;
  Progress bar(progress, "dataset", options.count, "images");
  int visible_count = 0;
  for (int i = 0; i < options.count; ++i) {
    if (i % kImagesPerScene == 0) {
      renderer = std::make_unique<RgbdRenderer>();
      scene = world.scene;
      scene.clutter_count = 10 + static_cast<int>(rng.Uniform(0.0, 30.0));
      scene.clutter_radius_m = rng.Uniform(1.5, 5.0);
      scene.pipe_radius_m = rng.Uniform(0.04, 0.15);
      for (const RenderMesh& m : BuildStaticScene(scene, options.seed * 1000003ull + i)) {
        renderer->AddMesh(m, RgbdRenderer::Motion::kStatic);
      }
      object_id = renderer->AddMesh(Tinted(object_mesh, &rng));
      occluder_ids.clear();
      distractor_ids.clear();
      for (int k = 0; k < kOccluders; ++k) {
        RenderMesh occluder;
        occluder.mesh =
            k % 2 ? MakeBoxMesh(Eigen::Vector3d(rng.Uniform(0.03, 0.3), rng.Uniform(0.03, 0.3),
                                                rng.Uniform(0.02, 0.1)))
                  : MakeCylinderMesh(rng.Uniform(0.01, 0.06), rng.Uniform(0.2, 0.8));
        occluder.material.albedo =
            Eigen::Vector3f(rng.Uniform(0.1, 1.0), rng.Uniform(0.1, 1.0), rng.Uniform(0.1, 1.0));
        occluder_ids.push_back(renderer->AddMesh(occluder));
      }
      for (const RenderMesh& d : distractor_meshes) distractor_ids.push_back(renderer->AddMesh(d));
      if (with_support_views) {
        for (int side = 0; side < 2; ++side) {
          arm_ids[side].clear();
          for (const RenderMesh& m : arm_meshes[side])
            arm_ids[side].push_back(renderer->AddMesh(m));
        }
      }
    }
    const bool support_view = with_support_views && rng.Uniform() < options.on_support;
    // The object is placed by its bounding-box centre (PlaceByCentre), whatever o's origin.
    Eigen::Isometry3d wMcentre = Eigen::Isometry3d::Identity(), wMc = Eigen::Isometry3d::Identity();
    double distance = 0.0;
    if (support_view) {
      // The object as the world places it (ObjectOnPipe): on top of the support pipe, its
      // x along the pipe (turned by a small yaw, or any yaw now and then).
      const double along = rng.Uniform(-0.45, 0.45) * scene.pipe_length_m;
      const double yaw = rng.Uniform() < 0.7
                             ? rng.Uniform(-0.2, 0.2) + (rng.Uniform() < 0.5 ? 0.0 : M_PI)
                             : rng.Uniform(-M_PI, M_PI);
      wMcentre = ObjectOnPipe(scene, object_half_height, along, yaw);
      // The vehicle's camera: 0.3-2.0 m away, above the pipe (elevation 25-80 deg), mostly from
      // across the pipe (as the mission approaches it), now and then from any side.
      const Eigen::Vector3d axis_w = PipeFrame(scene).linear().col(0);
      const double across =
          std::atan2(axis_w.x(), -axis_w.y()) + (rng.Uniform() < 0.5 ? 0.0 : M_PI);
      const double azimuth =
          across + (rng.Uniform() < 0.75 ? rng.Uniform(-0.6, 0.6) : rng.Uniform(-M_PI, M_PI));
      const double elevation = rng.Uniform(0.45, 1.4);
      distance = 0.3 + 1.7 * std::pow(rng.Uniform(), 1.2);
      const Eigen::Vector3d to_camera(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth),
                                      -std::sin(elevation));
      // The object anywhere in the image (8 %: out of view, the support pipe alone).
      const bool out_of_view = rng.Uniform() < 0.08;
      const double u = out_of_view ? (rng.Uniform() < 0.5 ? -400.0 : 1040.0)
                                   : rng.Uniform(-20.0, K.width + 20.0);
      const double v = rng.Uniform(-20.0, K.height + 20.0);
      wMc = CameraLookingAt(wMcentre.translation(), to_camera, distance, K, u, v,
                            rng.Uniform(-0.15, 0.15));
      // The arms where the vehicle carries them, joints near home.
      const Eigen::Isometry3d wMd = wMc * platform.dMc().inverse();
      for (Side side : kSides) {
        const ArmModel& arm = platform.arm(side);
        Eigen::VectorXd q = platform.home(side);
        for (int j = 0; j < q.size(); ++j) q[j] += rng.Uniform(-0.35, 0.35);
        std::vector<Eigen::Isometry3d> bMs;
        arm.SegmentPoses(arm.Clamp(q), &bMs);
        const std::vector<int>& ids = arm_ids[static_cast<int>(side)];
        for (std::size_t k = 0; k < ids.size() && k < bMs.size(); ++k) {
          renderer->SetPose(ids[k], wMd * platform.dMb(side) * bMs[k]);
        }
      }
    } else {
      for (const std::vector<int>& ids : arm_ids) {
        for (int id : ids)
          renderer->SetPose(id,
                            MakeTransform(Eigen::Vector3d(0, 0, 100.0), Eigen::Vector3d::Zero()));
      }
      // The object near the pipe, upright-ish most of the time.
      const Eigen::Vector3d pipe = world.scene.pipe_center_w_m;
      wMcentre.translation() =
          pipe +
          Eigen::Vector3d(rng.Uniform(-1.0, 1.0), rng.Uniform(-0.6, 0.6), rng.Uniform(-0.5, 1.0));
      if (rng.Uniform() < 0.6) {
        // z up in o is -z in NED: roll pi, then yaw and a small tilt.
        wMcentre.linear() = RotationFromRpy(Eigen::Vector3d(
            M_PI + rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3), rng.Uniform(-M_PI, M_PI)));
      } else {
        wMcentre.linear() = RandomRotation(&rng);
      }
      // The camera: distance 0.3-2.5 m (more samples near), above the object.
      distance = 0.3 + 2.2 * std::pow(rng.Uniform(), 1.3);
      const double azimuth = rng.Uniform(-M_PI, M_PI), elevation = rng.Uniform(0.05, 1.45);
      const Eigen::Vector3d to_camera(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth),
                                      -std::sin(elevation));
      // Put the object at a random pixel (10 % of the images: out of view).
      const bool out_of_view = rng.Uniform() < 0.1;
      const double u = out_of_view ? (rng.Uniform() < 0.5 ? -400.0 : 1040.0)
                                   : rng.Uniform(-20.0, K.width + 20.0);
      const double v = rng.Uniform(-20.0, K.height + 20.0);
      const double roll = rng.Uniform(-0.4, 0.4);
      wMc = CameraLookingAt(wMcentre.translation(), to_camera, distance, K, u, v, roll);
    }
    const Eigen::Isometry3d wMo = PlaceByCentre(wMcentre, object.mesh_o);
    renderer->SetPose(object_id, wMo);
    // Occluders between the camera and the object (sometimes), else far away.
    for (int id : occluder_ids) {
      Eigen::Isometry3d wMk = Eigen::Isometry3d::Identity();
      wMk.linear() = RandomRotation(&rng);
      if (rng.Uniform() < 0.3) {
        const double f = rng.Uniform(0.3, 0.8);
        wMk.translation() =
            wMc.translation() * (1.0 - f) + wMcentre.translation() * f +
            Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()) * 0.08 * distance;
      } else {
        wMk.translation() = Eigen::Vector3d(0, 0, 100.0);
      }
      renderer->SetPose(id, wMk);
    }
    for (int id : distractor_ids) {
      Eigen::Isometry3d wMk = Eigen::Isometry3d::Identity();
      wMk.linear() = RandomRotation(&rng);
      wMk.translation() = rng.Uniform() < 0.4
                              ? wMcentre.translation() + Eigen::Vector3d(rng.Uniform(-0.8, 0.8),
                                                                         rng.Uniform(-0.8, 0.8),
                                                                         rng.Uniform(-0.3, 0.3))
                              : Eigen::Vector3d(0, 0, 100.0);
      renderer->SetPose(id, wMk);
    }
    Lighting lighting;
    const double az = rng.Uniform(-M_PI, M_PI), el = rng.Uniform(0.3, 1.5);
    lighting.to_light_w =
        Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
    lighting.intensity = rng.Uniform(0.3, 1.3);
    lighting.ambient = rng.Uniform(0.15, 0.6);
    lighting.background =
        Eigen::Vector3f(rng.Uniform(0.3, 0.95), rng.Uniform(0.3, 0.95), rng.Uniform(0.4, 1.0));
    renderer->Render(wMc, K, lighting, &truth);
    SimulateD435(world.camera.d435, K, truth, &rng, &frame);

    PixelBox box{INT_MAX, INT_MAX, INT_MIN, INT_MIN};
    int pixels = 0;
    for (int y = 0; y < K.height; ++y) {
      for (int x = 0; x < K.width; ++x) {
        if (truth.object_id.at(x, y) != object_id) continue;
        ++pixels;
        box = {std::min(box.x0, x), std::min(box.y0, y), std::max(box.x1, x + 1),
               std::max(box.y1, y + 1)};
      }
    }
    const bool visible = pixels >= options.min_object_pixels;
    const PoseSupport support = ScorePoseSupport(model_cloud, wMc.inverse() * wMo, {}, frame.depth,
                                                 world.camera.d435.depth_scale_m, K);
    visible_count += visible;
    const ColorImage input = DetectorInput(frame.color);
    const cv::Mat rgb(input.height, input.width, CV_8UC3,
                      const_cast<std::uint8_t*>(input.data.data()));
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    const std::string path = (dir / "images" / fmt::format("{:06d}.png", i)).string();
    if (!cv::imwrite(path, bgr)) throw std::runtime_error(path + ": cannot be written");
    const double sx = double(kDetectorInputWidth) / K.width,
                 sy = double(kDetectorInputHeight) / K.height;
    if (visible) {
      labels << fmt::format("{},1,{:.2f},{:.2f},{:.2f},{:.2f},{},{:.3f}\n", i, box.x0 * sx,
                            box.y0 * sy, box.x1 * sx, box.y1 * sy, pixels, support.coverage());
    } else {
      labels << fmt::format("{},0,0,0,0,0,{},{:.3f}\n", i, pixels, support.coverage());
    }
    bar.Update(i + 1);
  }
  bar.Finish();
  labels.close();
  if (!labels) throw std::runtime_error((dir / "labels.csv").string() + ": cannot be written");
  folder.Commit();
  out << fmt::format("dataset: {} images of {} in {} ({} with the object visible), seed {}\n",
                     options.count, object.name, options.out_dir, visible_count, options.seed);
}

void AddDatasetOptions(CLI::App* cmd, DatasetCommandOptions* o) {
  cmd->add_option("--object", o->object, "Shipped object name or model path")->required();
  cmd->add_option("--out", o->out_dir, "Output folder")->required();
  cmd->add_option("--count", o->count, "Images")
      ->capture_default_str()
      ->check(cli::Range(1, 1000000));
  cmd->add_option("--seed", o->seed, "Seed (same seed, same images)")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_flag("--overwrite", o->overwrite, "Replace a dataset already in --out");
  cmd->add_option("--on-support", o->on_support,
                  "Fraction of images with the object lying on the support pipe, seen from the "
                  "vehicle's camera "
                  "with its arms in view")
      ->capture_default_str()
      ->check(cli::Range(0.0, 1.0));
}

}  // namespace aerograsp
