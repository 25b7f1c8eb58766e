#include "hardware/sim/scene.h"

#include <algorithm>
#include <cmath>

#include "core/random.h"
#include "core/shape_mesh.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kGroundSize_m = 60.0;
constexpr int kGroundTexturePixels = 256;  // 196 KB: stays in cache while rendering
constexpr int kGroundTextureTiles = 8;     // tiles per texture repeat

RenderMesh Solid(TriangleMesh mesh, const Eigen::Isometry3d& wMm, const Eigen::Vector3f& albedo) {
  RenderMesh r;
  AppendMesh(mesh, wMm, &r.mesh);
  r.material.albedo = albedo;
  return r;
}

}  // namespace

Eigen::Isometry3d PipeFrame(const SceneConfig& scene) {
  return MakeTransform(scene.pipe_center_w_m, Eigen::Vector3d(0.0, 0.0, scene.pipe_yaw_rad));
}

ColorImage MakeGroundTexture(int pixels, int tiles, std::uint64_t seed) {
  FastRandom rng(seed);
  std::vector<float> tile_shade(static_cast<std::size_t>(tiles * tiles));
  for (float& s : tile_shade) s = static_cast<float>(rng.Uniform(0.75, 1.0));
  ColorImage texture(pixels, pixels);
  const int tile_px = std::max(1, pixels / tiles);
  for (int y = 0; y < pixels; ++y) {
    for (int x = 0; x < pixels; ++x) {
      const int tx = std::min(tiles - 1, x / tile_px), ty = std::min(tiles - 1, y / tile_px);
      const bool joint = x % tile_px < 2 || y % tile_px < 2;
      const float shade = joint ? 0.45f : tile_shade[ty * tiles + tx] + 0.05f * rng.FastNormal();
      const float base[3] = {0.62f, 0.60f, 0.55f};  // concrete
      for (int c = 0; c < 3; ++c) {
        texture.at(x, y, c) =
            static_cast<std::uint8_t>(std::clamp(255.0f * base[c] * shade, 0.0f, 255.0f));
      }
    }
  }
  return texture;
}

Eigen::Isometry3d ObjectOnPipe(const SceneConfig& scene, double half_height_m, double along_m,
                               double yaw_rad) {
  const Eigen::Vector3d p_p(along_m, 0.0, -(scene.pipe_radius_m + half_height_m));
  // o's z up is -z of p (NED-like); o's x along the pipe, turned by yaw.
  const Eigen::Isometry3d pMo =
      MakeTransform(p_p, Eigen::Vector3d(M_PI, 0.0, 0.0)) *
      MakeTransform(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, yaw_rad));
  return PipeFrame(scene) * pMo;
}

std::vector<RenderMesh> ArmRenderMeshes(const ArmModel& arm) {
  std::vector<RenderMesh> meshes;
  for (const ArmSegment& segment : arm.segments()) {
    RenderMesh mesh;
    for (const CollisionShape& shape : segment.collision) {
      AppendMesh(MeshFromShape(shape), Eigen::Isometry3d::Identity(), &mesh.mesh);
    }
    mesh.material.albedo = {0.15f, 0.15f, 0.17f};
    meshes.push_back(std::move(mesh));
  }
  return meshes;
}

std::vector<RenderMesh> BuildStaticScene(const SceneConfig& scene, std::uint64_t seed) {
  FastRandom rng(seed);
  std::vector<RenderMesh> meshes;

  // Ground: a square at z = 0 facing up (-z in NED), texture repeated every tile group.
  RenderMesh ground;
  const double h = 0.5 * kGroundSize_m;
  ground.mesh.vertices = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  ground.mesh.triangles = {{0, 2, 1}, {0, 3, 2}};  // normal -z: up
  const float repeat =
      static_cast<float>(kGroundSize_m / (scene.ground_tile_m * kGroundTextureTiles));
  ground.uv = {{0, 0}, {repeat, 0}, {repeat, repeat}, {0, repeat}};
  ground.material.texture = std::make_shared<ColorImage>(
      MakeGroundTexture(kGroundTexturePixels, kGroundTextureTiles, seed ^ 0x6A09E667ull));
  meshes.push_back(std::move(ground));

  // The pipe along p's x axis, and two posts down to the ground.
  const Eigen::Isometry3d wMp = PipeFrame(scene);
  const Eigen::Isometry3d pMcylinder =
      MakeTransform(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, M_PI / 2, 0.0));
  meshes.push_back(Solid(MakeCylinderMesh(scene.pipe_radius_m, scene.pipe_length_m, 32),
                         wMp * pMcylinder, {0.55f, 0.57f, 0.60f}));
  const double post_height = -scene.pipe_center_w_m.z();
  for (double along : {-0.4 * scene.pipe_length_m, 0.4 * scene.pipe_length_m}) {
    const Eigen::Vector3d p_p(along, 0.0, 0.5 * post_height);
    meshes.push_back(Solid(MakeBoxMesh(Eigen::Vector3d(0.08, 0.08, post_height)),
                           wMp * MakeTransform(p_p, Eigen::Vector3d::Zero()),
                           {0.35f, 0.25f, 0.2f}));
  }

  // Clutter: boxes and upright cylinders on the ground, away from the pipe's footprint.
  const Eigen::Vector2d centre = scene.pipe_center_w_m.head<2>();
  for (int i = 0; i < scene.clutter_count; ++i) {
    const double r = scene.clutter_radius_m * std::sqrt(rng.Uniform(0.05, 1.0));
    const double a = rng.Uniform(0.0, 2.0 * M_PI);
    const Eigen::Vector2d xy = centre + r * Eigen::Vector2d(std::cos(a), std::sin(a));
    const Eigen::Vector3d size(rng.Uniform(0.1, 0.6), rng.Uniform(0.1, 0.6),
                               rng.Uniform(0.05, 0.5));
    const Eigen::Vector3f albedo(static_cast<float>(rng.Uniform(0.1, 0.9)),
                                 static_cast<float>(rng.Uniform(0.1, 0.9)),
                                 static_cast<float>(rng.Uniform(0.1, 0.9)));
    const Eigen::Isometry3d wMm =
        MakeTransform(Eigen::Vector3d(xy.x(), xy.y(), -0.5 * size.z()),
                      Eigen::Vector3d(0.0, 0.0, rng.Uniform(-M_PI, M_PI)));
    const bool box = rng.Uniform() < 0.6;
    meshes.push_back(Solid(box ? MakeBoxMesh(size) : MakeCylinderMesh(0.5 * size.x(), size.z(), 20),
                           wMm, albedo));
  }
  return meshes;
}

}  // namespace aerograsp
