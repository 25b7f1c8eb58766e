// Ray-cast rendering (Embree 3) of the simulated scene from the colour camera:
// shaded colour with vertex colours and textures, the true depth along the
// optical axis, and what the D435 depth model needs (incidence, surface
// darkness). The depth sensor's imperfections are applied afterwards by
// D435DepthModel (hardware/sim/depth_model.h). Embree stays in the .cpp.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/mesh.h"

namespace aerograsp {

/// How a surface looks. With a texture the colour is texture x albedo, with
/// vertex colours it is vertex colour x albedo, else albedo.
struct RenderMaterial {
  Eigen::Vector3f albedo{1.0f, 1.0f, 1.0f};   ///< RGB reflectance, each in [0, 1]
  std::shared_ptr<const ColorImage> texture;  ///< optional, sampled by per-vertex uv
};

/// A mesh to render, in its own frame; posed in the world with SetPose().
struct RenderMesh {
  TriangleMesh mesh;
  /// per vertex, in [0, 1] (u right, v down); needed with a texture
  std::vector<Eigen::Vector2f> uv;
  RenderMaterial material;
};

/// One directional light plus ambient light.
struct Lighting {
  Eigen::Vector3d to_light_w{0.3, -0.2,
                             -1.0};  ///< direction towards the light, world frame (any length)
  double intensity = 0.8;            ///< directional part, [0, 2]
  double ambient = 0.35;             ///< ambient part, [0, 1]
  Eigen::Vector3f background{0.62f, 0.72f, 0.85f};  ///< colour where no surface is hit (sky)
};

/// What one render produces, all width x height of the intrinsics.
struct RenderBuffers {
  ColorImage color;          ///< shaded RGB, no noise
  FloatImage depth_m;        ///< true z along the optical axis (m); 0 where nothing is hit
  FloatImage cos_incidence;  ///< |cos| of the angle between ray and surface normal; 0 where no hit
  FloatImage darkness;       ///< 1 - reflectance luminance of the surface (0 bright .. 1 black)
  Image<std::int32_t, 1> object_id;  ///< id from AddMesh of the surface hit; -1 where no hit
};

class RgbdRenderer {
 public:
  RgbdRenderer();
  ~RgbdRenderer();
  RgbdRenderer(const RgbdRenderer&) = delete;
  RgbdRenderer& operator=(const RgbdRenderer&) = delete;

  /// kStatic meshes are given in the world frame and never move (they share
  /// one acceleration structure, the cheapest to trace); kMovable meshes are
  /// instances posed with SetPose().
  enum class Motion { kStatic, kMovable };

  /// Adds a mesh, visible, at the identity pose. Returns its id (0, 1, ...).
  /// @throws std::invalid_argument when uv is given with the wrong size, or a
  /// texture without uv.
  int AddMesh(const RenderMesh& mesh, Motion motion = Motion::kMovable);
  /// wMm: the mesh frame in the world frame.
  /// @throws std::invalid_argument for a static mesh.
  void SetPose(int id, const Eigen::Isometry3d& wMm);
  void SetVisible(int id, bool visible);
  int mesh_count() const;

  /// Renders the scene seen from the camera at `wMc` (optical frame c: z along
  /// the view, x right, y down) with intrinsics K. Pixel (u, v) samples the ray
  /// through its centre at integer coordinates, matching CameraIntrinsics::Project.
  void Render(const Eigen::Isometry3d& wMc, const CameraIntrinsics& K, const Lighting& lighting,
              RenderBuffers* out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
