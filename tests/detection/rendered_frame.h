// A simulated D435 frame of a test scene, for the detection tests that render one.
#pragma once

#include <Eigen/Geometry>

#include "hardware/sim/d435_model.h"
#include "hardware/sim/rgbd_renderer.h"

namespace aerograsp::testing {

/// Renders `renderer`'s scene from a camera at the world origin (light from above and
/// to the side) and passes it through the D435 model with its default settings.
/// `truth` (optional): the render before the depth model (which mesh each pixel shows).
inline void RenderD435Frame(RgbdRenderer& renderer, const CameraIntrinsics& K, FastRandom* rng,
                            ColorImage* color, DepthImage* depth, RenderBuffers* truth = nullptr) {
  RenderBuffers rendered;
  Lighting light;
  light.to_light_w = Eigen::Vector3d(0.2, -0.5, -1.0);
  renderer.Render(Eigen::Isometry3d::Identity(), K, light, &rendered);
  RgbdFrame frame;
  SimulateD435(D435Config{}, K, rendered, rng, &frame);
  if (truth) *truth = rendered;
  *color = frame.color;
  *depth = frame.depth;
}

}  // namespace aerograsp::testing
