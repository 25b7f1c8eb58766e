// The static scene around the object: textured ground, the support pipe on
// two posts, and clutter, so that the camera sees a background.
#pragma once

#include <cstdint>
#include <vector>

#include "core/arm_model.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {

/// wMp: the pipe frame p (origin on the pipe's axis at its centre, x along the
/// axis, z down like w) in the world.
Eigen::Isometry3d PipeFrame(const SceneConfig& scene);

/// The pose in w of the centre of an object lying on top of the pipe `along_m`
/// from the pipe's centre, with o's axes (z up, x along the pipe turned by
/// `yaw_rad`), its lowest point `half_height_m` below that centre. The object's
/// wMo is PlaceByCentre of it (core/object_model.h).
Eigen::Isometry3d ObjectOnPipe(const SceneConfig& scene, double half_height_m, double along_m,
                               double yaw_rad);

/// Render meshes of an arm's segments (frames as ArmModel::SegmentPoses), made
/// from their collision shapes: black servos and brackets.
std::vector<RenderMesh> ArmRenderMeshes(const ArmModel& arm);

/// The scene's meshes, already in w. The same seed gives the same clutter.
std::vector<RenderMesh> BuildStaticScene(const SceneConfig& scene, std::uint64_t seed);

/// A square texture of `tiles` x `tiles` slightly different tiles with noise
/// (the ground: concrete slabs), `pixels` wide.
ColorImage MakeGroundTexture(int pixels, int tiles, std::uint64_t seed);

}  // namespace aerograsp
