// A simulated RealSense-like recording for the tests of recordings: the default
// world's scene rendered from a colour camera and, separately, from a depth
// camera with its own intrinsics, offset by a known extrinsic (unaligned depth,
// as a D435 delivers it), with the object's true pose in the colour camera.
#pragma once

#include <cmath>
#include <vector>

#include "core/data_dir.h"
#include "core/transforms.h"
#include "hardware/rgbd_alignment.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/world.h"

namespace aerograsp::testing {

struct SimulatedFrame {
  ColorImage color;
  DepthImage depth;        ///< the depth camera's own image, in depth units
  DepthImage color_depth;  ///< depth rendered from the colour camera (the aligned truth)
  Eigen::Isometry3d cMo;   ///< object in the colour camera
};

struct SimulatedRecording {
  StreamCalibration color, depth;
  Eigen::Isometry3d colorMdepth;
  double depth_scale_m = 0.001;
  std::string object;
  std::vector<SimulatedFrame> frames;
};

/// Intrinsics and extrinsic of a real D435 recording (librealsense's sample; depth
/// fx 390.43, colour fx 613.20; depth to colour about 14 mm along x).
inline SimulatedRecording D435LikeStreams() {
  SimulatedRecording r;
  r.color.intrinsics = {640, 480, 613.20, 613.42, 319.94, 239.18};
  r.color.model = DistortionModel::kBrownConrady;
  r.depth.intrinsics = {640, 480, 390.43, 390.43, 331.39, 242.19};
  r.depth.model = DistortionModel::kBrownConrady;
  r.colorMdepth =
      MakeTransform(Eigen::Vector3d(0.0147, 0.0006, 0.0004), Eigen::Vector3d(0.002, 0.013, 0.010));
  return r;
}

inline DepthImage Quantise(const FloatImage& depth_m, double scale_m) {
  DepthImage d(depth_m.width, depth_m.height);
  for (std::size_t i = 0; i < d.data.size(); ++i)
    d.data[i] = static_cast<std::uint16_t>(std::lround(depth_m.data[i] / scale_m));
  return d;
}

/// `count` frames of the default world (static object; `object` instead of its
/// own when given), the vehicle swaying as it hovers.
inline SimulatedRecording SimulateRecording(int count, const std::string& object = "",
                                            double frame_rate_hz = 30.0) {
  SimulatedRecording r = D435LikeStreams();
  WorldConfig config = WorldConfig::Load(DataPath("config/world_default.yaml"));
  if (!object.empty()) config.object.name = object;
  World world(config, 7);
  r.object = world.object().name;
  RgbdRenderer renderer;
  for (const RenderMesh& m : world.static_scene())
    renderer.AddMesh(m, RgbdRenderer::Motion::kStatic);
  const int object_id = renderer.AddMesh(world.object_render_mesh());
  RenderBuffers color, depth;
  for (int i = 0; i < count; ++i) {
    world.StepTo(i / frame_rate_hz);
    renderer.SetPose(object_id, world.wMo());
    const Eigen::Isometry3d wMc = world.wMc();
    renderer.Render(wMc, r.color.intrinsics, Lighting{}, &color);
    renderer.Render(wMc * r.colorMdepth, r.depth.intrinsics, Lighting{}, &depth);
    SimulatedFrame f;
    f.color = color.color;
    f.color_depth = Quantise(color.depth_m, r.depth_scale_m);
    f.depth = Quantise(depth.depth_m, r.depth_scale_m);
    f.cMo = wMc.inverse() * world.wMo();
    r.frames.push_back(std::move(f));
  }
  return r;
}

}  // namespace aerograsp::testing
