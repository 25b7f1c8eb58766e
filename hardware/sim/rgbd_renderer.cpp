#include "hardware/sim/rgbd_renderer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace aerograsp {
namespace {

constexpr int kPacket = 8;  // rays per rtcIntersect8 call: 8 neighbouring pixels of a row

/// The per-mesh data shading needs, in the mesh frame.
struct MeshData {
  RTCScene scene = nullptr;
  RTCGeometry instance = nullptr;
  std::vector<Eigen::Vector3f> face_normals;
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Eigen::Vector3f> vertex_colors;  // 0..1; empty when none
  std::vector<Eigen::Vector2f> uv;             // empty without a texture
  RenderMaterial material;
  Eigen::Matrix3f wRm = Eigen::Matrix3f::Identity();
  bool visible = true;
};

float Luminance(const Eigen::Vector3f& rgb) {
  return 0.2126f * rgb.x() + 0.7152f * rgb.y() + 0.0722f * rgb.z();
}

std::uint8_t ToByte(float value) {
  return static_cast<std::uint8_t>(std::clamp(value * 255.0f + 0.5f, 0.0f, 255.0f));
}

Eigen::Vector3f SampleTexture(const ColorImage& texture, const Eigen::Vector2f& uv) {
  const float u = uv.x() - std::floor(uv.x()), v = uv.y() - std::floor(uv.y());  // repeat
  const int x = std::min(texture.width - 1, static_cast<int>(u * texture.width));
  const int y = std::min(texture.height - 1, static_cast<int>(v * texture.height));
  const std::uint8_t* p = &texture.at(x, y);
  return Eigen::Vector3f(p[0], p[1], p[2]) / 255.0f;
}

}  // namespace

struct RgbdRenderer::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  bool dirty = true;
  std::vector<MeshData> meshes;

  Impl() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    top = rtcNewScene(device);
    rtcSetSceneBuildQuality(top, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(top, RTC_SCENE_FLAG_DYNAMIC);
  }
  ~Impl() {
    for (auto& m : meshes) {
      rtcReleaseGeometry(m.instance);
      rtcReleaseScene(m.scene);
    }
    rtcReleaseScene(top);
    rtcReleaseDevice(device);
  }
};

RgbdRenderer::RgbdRenderer() : impl_(std::make_unique<Impl>()) {}
RgbdRenderer::~RgbdRenderer() = default;

int RgbdRenderer::mesh_count() const { return static_cast<int>(impl_->meshes.size()); }

int RgbdRenderer::AddMesh(const RenderMesh& in) {
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
  data.scene = rtcNewScene(impl_->device);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
      mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
      mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
    data.face_normals.push_back(mesh.TriangleNormal(i).cast<float>());
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(data.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(data.scene);

  data.triangles = mesh.triangles;
  for (const auto& c : mesh.colors) data.vertex_colors.emplace_back(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f);
  data.uv = in.uv;
  data.material = in.material;

  data.instance = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(data.instance, data.scene);
  const int id = static_cast<int>(impl_->meshes.size());
  impl_->meshes.push_back(std::move(data));
  SetPose(id, Eigen::Isometry3d::Identity());
  rtcAttachGeometryByID(impl_->top, impl_->meshes.back().instance, static_cast<unsigned>(id));
  impl_->dirty = true;
  return id;
}

void RgbdRenderer::SetPose(int id, const Eigen::Isometry3d& wMm) {
  MeshData& m = impl_->meshes.at(static_cast<std::size_t>(id));
  float xfm[12];  // 3x4 column major
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) xfm[3 * c + r] = static_cast<float>(wMm.matrix()(r, c));
  }
  rtcSetGeometryTransform(m.instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  rtcCommitGeometry(m.instance);
  m.wRm = wMm.linear().cast<float>();
  impl_->dirty = true;
}

void RgbdRenderer::SetVisible(int id, bool visible) {
  MeshData& m = impl_->meshes.at(static_cast<std::size_t>(id));
  if (m.visible == visible) return;
  m.visible = visible;
  if (visible) {
    rtcEnableGeometry(m.instance);
  } else {
    rtcDisableGeometry(m.instance);
  }
  rtcCommitGeometry(m.instance);
  impl_->dirty = true;
}

void RgbdRenderer::Render(const Eigen::Isometry3d& wMc, const CameraIntrinsics& K,
                          const Lighting& lighting, RenderBuffers* out) {
  if (impl_->dirty) {
    rtcCommitScene(impl_->top);
    impl_->dirty = false;
  }
  const int W = K.width, H = K.height;
  out->color = ColorImage(W, H);
  out->depth_m = FloatImage(W, H, 0.0f);
  out->cos_incidence = FloatImage(W, H, 0.0f);
  out->darkness = FloatImage(W, H, 0.0f);
  out->object_id = Image<std::int32_t, 1>(W, H, -1);

  const Eigen::Matrix3f wRc = wMc.linear().cast<float>();
  const Eigen::Vector3f origin = wMc.translation().cast<float>();
  const Eigen::Vector3f to_light = lighting.to_light_w.cast<float>().normalized();
  const float ambient = static_cast<float>(lighting.ambient);
  const float intensity = static_cast<float>(lighting.intensity);
  const std::array<std::uint8_t, 3> background = {ToByte(lighting.background.x()),
                                                  ToByte(lighting.background.y()),
                                                  ToByte(lighting.background.z())};

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(32) RTCRayHit8 packet;
  alignas(32) int valid[kPacket];
  Eigen::Vector3f dirs[kPacket];

  for (int y = 0; y < H; ++y) {
    const float yc = static_cast<float>((y - K.cy) / K.fy);
    for (int x0 = 0; x0 < W; x0 += kPacket) {
      for (int k = 0; k < kPacket; ++k) {
        const int x = x0 + k;
        valid[k] = x < W ? -1 : 0;
        const Eigen::Vector3f d_c(static_cast<float>((x - K.cx) / K.fx), yc, 1.0f);
        dirs[k] = wRc * d_c;  // z component in c is 1: the hit distance t is the depth z
        packet.ray.org_x[k] = origin.x();
        packet.ray.org_y[k] = origin.y();
        packet.ray.org_z[k] = origin.z();
        packet.ray.dir_x[k] = dirs[k].x();
        packet.ray.dir_y[k] = dirs[k].y();
        packet.ray.dir_z[k] = dirs[k].z();
        packet.ray.tnear[k] = 0.0f;
        packet.ray.tfar[k] = std::numeric_limits<float>::infinity();
        packet.ray.time[k] = 0.0f;
        packet.ray.mask[k] = 0xFFFFFFFFu;
        packet.ray.id[k] = static_cast<unsigned>(k);
        packet.ray.flags[k] = 0;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, impl_->top, &context, &packet);
      for (int k = 0; k < kPacket && x0 + k < W; ++k) {
        const int x = x0 + k;
        std::uint8_t* rgb = &out->color.at(x, y);
        const unsigned inst = packet.hit.instID[0][k];
        if (packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID || inst == RTC_INVALID_GEOMETRY_ID) {
          std::copy(background.begin(), background.end(), rgb);
          continue;
        }
        const MeshData& m = impl_->meshes[inst];
        const unsigned prim = packet.hit.primID[k];
        const float bu = packet.hit.u[k], bv = packet.hit.v[k], bw = 1.0f - bu - bv;
        const Eigen::Vector3f dir_unit = dirs[k].normalized();
        Eigen::Vector3f n_w = m.wRm * m.face_normals[prim];
        float cos_view = n_w.dot(dir_unit);
        if (cos_view > 0.0f) {  // back face: shade the side the camera sees
          n_w = -n_w;
          cos_view = -cos_view;
        }
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
        const float shade = ambient + intensity * std::max(0.0f, n_w.dot(to_light));
        for (int c = 0; c < 3; ++c) rgb[c] = ToByte(reflectance[c] * shade);
        out->depth_m.at(x, y) = packet.ray.tfar[k];
        out->cos_incidence.at(x, y) = -cos_view;
        out->darkness.at(x, y) = 1.0f - std::clamp(Luminance(reflectance), 0.0f, 1.0f);
        out->object_id.at(x, y) = static_cast<std::int32_t>(inst);
      }
    }
  }
}

}  // namespace aerograsp
