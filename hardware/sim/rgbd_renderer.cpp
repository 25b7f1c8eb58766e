#include "hardware/sim/rgbd_renderer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace aerograsp {
namespace {

// Rays per rtcIntersect16 call: a tile of 8 x 2 neighbouring pixels.
constexpr int kTileW = 8, kTileH = 2, kPacket = kTileW * kTileH;
// One build thread (the budget is per core); kernels no wider than AVX2, so a
// CPU with AVX-512 traces with the same kernels as one with AVX2 (kernels of
// another width differ in a depth's last bits, enough to fly a seed otherwise).
constexpr const char* kEmbreeDeviceConfig = "threads=1,max_isa=avx2";

/// One triangle's shading for the frame being rendered: what depends on the
/// pose and the lighting but not on the pixel. Side 0 is the one its normal
/// points to, side 1 the back (seen when the camera looks at the back face).
struct FaceShade {
  Eigen::Vector3f n_w;     // unit normal in w
  float shade[2];          // ambient + directional light on each side
  std::uint8_t rgb[2][3];  // colour on each side; only for a plain albedo (MeshData::plain)
};

/// The per-mesh data shading needs, in the mesh frame.
struct MeshData {
  RTCScene scene = nullptr;        // movable meshes: the instanced scene
  RTCGeometry geometry = nullptr;  // the geometry attached to the top scene
  bool movable = true;
  std::vector<Eigen::Vector3f> face_normals;
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Eigen::Vector3f> vertex_colors;  // 0..1; empty when none
  std::vector<Eigen::Vector2f> uv;             // empty without a texture
  RenderMaterial material;
  Eigen::Matrix3f wRm = Eigen::Matrix3f::Identity();
  bool visible = true;
  // Neither vertex colours nor texture: the reflectance is the albedo on the
  // whole mesh, so colour and darkness follow from the face alone.
  bool plain = true;
  float plain_darkness = 0.0f;
  std::vector<FaceShade> faces;  // per triangle, for the current Render
};

float Luminance(const Eigen::Vector3f& rgb) {
  return 0.2126f * rgb.x() + 0.7152f * rgb.y() + 0.0722f * rgb.z();
}

std::uint8_t ToByte(float value) {
  const float v = value * 255.0f + 0.5f;
  return static_cast<std::uint8_t>(v < 0.0f ? 0.0f : (v > 255.0f ? 255.0f : v));
}

/// The fractional part, in [0, 1) (floorf is a library call without SSE4.1).
float Fraction(float value) {
  int i = static_cast<int>(value);
  if (value < static_cast<float>(i)) --i;
  return value - static_cast<float>(i);
}

/// b / 255 for every byte b: a load instead of a conversion and a multiply
/// per channel (the same floats).
struct ByteToUnit {
  float value[256];
  ByteToUnit() {
    for (int b = 0; b < 256; ++b) value[b] = static_cast<float>(b) * (1.0f / 255.0f);
  }
};
const ByteToUnit kByteToUnit;

Eigen::Vector3f SampleTexture(const ColorImage& texture, const Eigen::Vector2f& uv) {
  const float u = Fraction(uv.x()), v = Fraction(uv.y());  // the texture repeats
  const int x = std::min(texture.width - 1, static_cast<int>(u * texture.width));
  const int y = std::min(texture.height - 1, static_cast<int>(v * texture.height));
  const std::uint8_t* p = &texture.at(x, y);
  return Eigen::Vector3f(kByteToUnit.value[p[0]], kByteToUnit.value[p[1]], kByteToUnit.value[p[2]]);
}

/// Gives `image` the size; the values are left as they are (Render writes
/// every pixel).
template <typename T, int C>
void Resize(int width, int height, Image<T, C>* image) {
  if (image->width != width || image->height != height) *image = Image<T, C>(width, height);
}

}  // namespace

// Two levels: the static meshes share one scene, built once with high
// quality and instanced once in the top scene; each movable mesh is an
// instance of its own scene. Moving a mesh only rebuilds the small top level.
struct RgbdRenderer::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  RTCScene statics = nullptr;
  RTCGeometry statics_instance = nullptr;
  bool top_dirty = true, statics_dirty = false;
  std::vector<MeshData> meshes;     // by id
  std::vector<int> mesh_of_top;     // top-level geometry ID -> mesh id (-1: the statics instance)
  std::vector<int> mesh_of_static;  // geometry ID in `statics` -> mesh id

  Impl() {
    device = rtcNewDevice(kEmbreeDeviceConfig);
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    top = rtcNewScene(device);
    rtcSetSceneBuildQuality(top, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(top, RTC_SCENE_FLAG_DYNAMIC);
    statics = rtcNewScene(device);
    rtcSetSceneBuildQuality(statics, RTC_BUILD_QUALITY_HIGH);
    statics_instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(statics_instance, statics);
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    rtcSetGeometryTransform(statics_instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
    rtcCommitGeometry(statics_instance);
    mesh_of_top.push_back(-1);
    rtcAttachGeometryByID(top, statics_instance, 0);
  }
  ~Impl() {
    for (auto& m : meshes) {
      rtcReleaseGeometry(m.geometry);
      if (m.scene) rtcReleaseScene(m.scene);
    }
    rtcReleaseGeometry(statics_instance);
    rtcReleaseScene(statics);
    rtcReleaseScene(top);
    rtcReleaseDevice(device);
  }
  /// Mesh id of a hit: an instance of a movable mesh, or a geometry of the statics.
  int MeshOfHit(unsigned inst, unsigned geom) const {
    const int top_mesh = mesh_of_top[inst];
    return top_mesh >= 0 ? top_mesh : mesh_of_static[geom];
  }
};

RgbdRenderer::RgbdRenderer() : impl_(std::make_unique<Impl>()) {}
RgbdRenderer::~RgbdRenderer() = default;

int RgbdRenderer::mesh_count() const { return static_cast<int>(impl_->meshes.size()); }

int RgbdRenderer::AddMesh(const RenderMesh& in, Motion motion) {
  const TriangleMesh& mesh = in.mesh;
  if (!in.uv.empty() && in.uv.size() != mesh.vertices.size()) {
    throw std::invalid_argument("RgbdRenderer::AddMesh: " + std::to_string(in.uv.size()) +
                                " uv coordinates for " + std::to_string(mesh.vertices.size()) +
                                " vertices");
  }
  if (in.material.texture && in.uv.empty()) {
    throw std::invalid_argument("RgbdRenderer::AddMesh: a texture needs per-vertex uv coordinates");
  }
  MeshData data;
  RTCGeometry triangles = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(triangles, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(triangles, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
    data.face_normals.push_back(mesh.TriangleNormal(i).cast<float>());
  }
  rtcCommitGeometry(triangles);
  data.movable = motion == Motion::kMovable;
  if (data.movable) {
    data.scene = rtcNewScene(impl_->device);
    rtcAttachGeometry(data.scene, triangles);
    rtcReleaseGeometry(triangles);
    rtcCommitScene(data.scene);
    data.geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(data.geometry, data.scene);
  } else {
    data.geometry = triangles;
  }
  data.triangles = mesh.triangles;
  for (const auto& c : mesh.colors)
    data.vertex_colors.emplace_back(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f);
  data.uv = in.uv;
  data.material = in.material;
  data.plain = data.vertex_colors.empty() && !data.material.texture;
  data.plain_darkness = 1.0f - std::min(1.0f, Luminance(data.material.albedo));
  data.faces.resize(data.triangles.size());

  const int id = static_cast<int>(impl_->meshes.size());
  impl_->meshes.push_back(std::move(data));
  MeshData& added = impl_->meshes.back();
  if (added.movable) {
    SetPose(id, Eigen::Isometry3d::Identity());
    rtcAttachGeometryByID(impl_->top, added.geometry,
                          static_cast<unsigned>(impl_->mesh_of_top.size()));
    impl_->mesh_of_top.push_back(id);
    impl_->top_dirty = true;
  } else {
    rtcAttachGeometryByID(impl_->statics, added.geometry,
                          static_cast<unsigned>(impl_->mesh_of_static.size()));
    impl_->mesh_of_static.push_back(id);
    impl_->statics_dirty = true;
  }
  return id;
}

void RgbdRenderer::SetPose(int id, const Eigen::Isometry3d& wMm) {
  MeshData& m = impl_->meshes.at(static_cast<std::size_t>(id));
  if (!m.movable)
    throw std::invalid_argument("RgbdRenderer::SetPose: mesh " + std::to_string(id) + " is static");
  float xfm[12];  // 3x4 column major
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) xfm[3 * c + r] = static_cast<float>(wMm.matrix()(r, c));
  }
  rtcSetGeometryTransform(m.geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  rtcCommitGeometry(m.geometry);
  m.wRm = wMm.linear().cast<float>();
  impl_->top_dirty = true;
}

void RgbdRenderer::SetVisible(int id, bool visible) {
  MeshData& m = impl_->meshes.at(static_cast<std::size_t>(id));
  if (m.visible == visible) return;
  m.visible = visible;
  if (visible) {
    rtcEnableGeometry(m.geometry);
  } else {
    rtcDisableGeometry(m.geometry);
  }
  rtcCommitGeometry(m.geometry);
  (m.movable ? impl_->top_dirty : impl_->statics_dirty) = true;
}

void RgbdRenderer::Render(const Eigen::Isometry3d& wMc, const CameraIntrinsics& K,
                          const Lighting& lighting, RenderBuffers* out) {
  if (impl_->statics_dirty) {
    rtcCommitScene(impl_->statics);
    rtcCommitGeometry(impl_->statics_instance);
    impl_->statics_dirty = false;
    impl_->top_dirty = true;
  }
  if (impl_->top_dirty) {
    rtcCommitScene(impl_->top);
    impl_->top_dirty = false;
  }
  const int W = K.width, H = K.height;
  Resize(W, H, &out->color);
  Resize(W, H, &out->depth_m);
  Resize(W, H, &out->cos_incidence);
  Resize(W, H, &out->darkness);
  Resize(W, H, &out->object_id);

  const Eigen::Matrix3f wRc = wMc.linear().cast<float>();
  const Eigen::Vector3f origin = wMc.translation().cast<float>();
  const Eigen::Vector3f to_light = lighting.to_light_w.cast<float>().normalized();
  const float ambient = static_cast<float>(lighting.ambient);
  const float intensity = static_cast<float>(lighting.intensity);
  const std::uint8_t background[3] = {ToByte(lighting.background.x()),
                                      ToByte(lighting.background.y()),
                                      ToByte(lighting.background.z())};
  // Per triangle of the visible meshes: normal, light and (plain meshes)
  // colour, once per frame instead of once per pixel.
  for (MeshData& m : impl_->meshes) {
    if (!m.visible) continue;
    for (std::size_t i = 0; i < m.faces.size(); ++i) {
      FaceShade& f = m.faces[i];
      f.n_w = m.movable ? Eigen::Vector3f(m.wRm * m.face_normals[i]) : m.face_normals[i];
      f.shade[0] = ambient + intensity * std::max(0.0f, f.n_w.dot(to_light));
      f.shade[1] = ambient + intensity * std::max(0.0f, (-f.n_w).dot(to_light));
      if (m.plain) {
        for (int side = 0; side < 2; ++side) {
          for (int c = 0; c < 3; ++c) f.rgb[side][c] = ToByte(m.material.albedo[c] * f.shade[side]);
        }
      }
    }
  }

  // Ray directions in c have z = 1, so the hit distance t is the depth z. In
  // w: d = wRc (x_c, y_c, 1) = column part (per x) + row part (per y).
  std::vector<Eigen::Vector3f> column_w(W), row_w(H);
  for (int x = 0; x < W; ++x) column_w[x] = wRc.col(0) * static_cast<float>((x - K.cx) / K.fx);
  for (int y = 0; y < H; ++y)
    row_w[y] = wRc.col(1) * static_cast<float>((y - K.cy) / K.fy) + wRc.col(2);

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[kPacket];
  // Embree writes only tfar and the hit: the rest of the rays is set once.
  for (int k = 0; k < kPacket; ++k) {
    packet.ray.org_x[k] = origin.x();
    packet.ray.org_y[k] = origin.y();
    packet.ray.org_z[k] = origin.z();
    packet.ray.tnear[k] = 0.0f;
    packet.ray.time[k] = 0.0f;
    packet.ray.mask[k] = 0xFFFFFFFFu;
    packet.ray.id[k] = static_cast<unsigned>(k);
    packet.ray.flags[k] = 0;
  }

  for (int y0 = 0; y0 < H; y0 += kTileH) {
    for (int x0 = 0; x0 < W; x0 += kTileW) {
      for (int k = 0; k < kPacket; ++k) {
        const int x = x0 + k % kTileW, y = y0 + k / kTileW;
        const bool inside = x < W && y < H;
        valid[k] = inside ? -1 : 0;
        const Eigen::Vector3f dir = inside ? Eigen::Vector3f(column_w[x] + row_w[y]) : row_w[0];
        packet.ray.dir_x[k] = dir.x();
        packet.ray.dir_y[k] = dir.y();
        packet.ray.dir_z[k] = dir.z();
        packet.ray.tfar[k] = std::numeric_limits<float>::infinity();
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, impl_->top, &context, &packet);
      for (int k = 0; k < kPacket; ++k) {
        if (!valid[k]) continue;
        const std::size_t pixel = static_cast<std::size_t>(y0 + k / kTileW) * W + (x0 + k % kTileW);
        std::uint8_t* rgb = &out->color.data[3 * pixel];
        if (packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
          rgb[0] = background[0];
          rgb[1] = background[1];
          rgb[2] = background[2];
          out->depth_m.data[pixel] = 0.0f;
          out->cos_incidence.data[pixel] = 0.0f;
          out->darkness.data[pixel] = 0.0f;
          out->object_id.data[pixel] = -1;
          continue;
        }
        const int id = impl_->MeshOfHit(packet.hit.instID[0][k], packet.hit.geomID[k]);
        const MeshData& m = impl_->meshes[static_cast<std::size_t>(id)];
        const unsigned prim = packet.hit.primID[k];
        const FaceShade& face = m.faces[prim];
        const Eigen::Vector3f dir(packet.ray.dir_x[k], packet.ray.dir_y[k], packet.ray.dir_z[k]);
        const float cos_view = face.n_w.dot(dir) / dir.norm();
        const int side = cos_view > 0.0f ? 1 : 0;  // back face: shade the side the camera sees
        if (m.plain) {
          rgb[0] = face.rgb[side][0];
          rgb[1] = face.rgb[side][1];
          rgb[2] = face.rgb[side][2];
          out->darkness.data[pixel] = m.plain_darkness;
        } else {
          const float bu = packet.hit.u[k], bv = packet.hit.v[k], bw = 1.0f - bu - bv;
          Eigen::Vector3f reflectance = m.material.albedo;
          const Eigen::Vector3i& tri = m.triangles[prim];
          if (!m.vertex_colors.empty()) {
            reflectance = reflectance.cwiseProduct(bw * m.vertex_colors[tri[0]] +
                                                   bu * m.vertex_colors[tri[1]] +
                                                   bv * m.vertex_colors[tri[2]]);
          }
          if (m.material.texture) {
            const Eigen::Vector2f uv = bw * m.uv[tri[0]] + bu * m.uv[tri[1]] + bv * m.uv[tri[2]];
            reflectance = reflectance.cwiseProduct(SampleTexture(*m.material.texture, uv));
          }
          const float shade = face.shade[side];
          for (int c = 0; c < 3; ++c) rgb[c] = ToByte(reflectance[c] * shade);
          out->darkness.data[pixel] = 1.0f - std::min(1.0f, Luminance(reflectance));
        }
        out->depth_m.data[pixel] = packet.ray.tfar[k];
        out->cos_incidence.data[pixel] = side ? cos_view : -cos_view;
        out->object_id.data[pixel] = static_cast<std::int32_t>(id);
      }
    }
  }
}

}  // namespace aerograsp
