#include "grasp/contacts.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/config.h"

namespace aerograsp {
namespace {

/// Rays at less than this cosine to a face are grazing it: their hits are
/// unreliable, so the ray is dropped.
constexpr double kGrazingCos = 1e-3;

/// One Embree device for the process (created on first use, thread-safe
/// initialisation; one build thread so contact generation stays on one core;
/// kernels no wider than AVX2, so contacts come out alike on AVX2 and AVX-512 CPUs).
RTCDevice SharedDevice() {
  static const std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)> device(
      rtcNewDevice("threads=1,set_affinity=0,max_isa=avx2"), rtcReleaseDevice);
  if (!device) throw std::runtime_error("Embree: cannot create a device");
  return device.get();
}

struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneDeleter>;

ScenePtr BuildScene(const TriangleMesh& mesh) {
  RTCDevice device = SharedDevice();
  ScenePtr scene(rtcNewScene(device));
  rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                           RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                           mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) t[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene.get(), geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene.get());
  return scene;
}

struct Hit {
  double t;
  unsigned prim;
};

/// Every hit along the ray origin + t dir, t in [0, t_max], sorted by t. Hits
/// closer than `min_step` to the previous one (a ray through an edge shared by
/// two triangles) count once.
void AllHits(RTCScene scene, const Eigen::Vector3d& origin, int axis, double t_max, double min_step,
             std::vector<Hit>* hits) {
  hits->clear();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  double t_near = 0.0;
  while (t_near <= t_max) {
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(origin.x());
    rh.ray.org_y = static_cast<float>(origin.y());
    rh.ray.org_z = static_cast<float>(origin.z());
    rh.ray.dir_x = axis == 0 ? 1.0f : 0.0f;
    rh.ray.dir_y = axis == 1 ? 1.0f : 0.0f;
    rh.ray.dir_z = axis == 2 ? 1.0f : 0.0f;
    rh.ray.tnear = static_cast<float>(t_near);
    rh.ray.tfar = static_cast<float>(t_max);
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
    hits->push_back({static_cast<double>(rh.ray.tfar), rh.hit.primID});
    t_near = rh.ray.tfar + min_step;
  }
}

}  // namespace

void ContactOptions::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "resolution_m", resolution_m, 0.001, 0.1, "m");
}

ContactSet ComputeContactPairs(const TriangleMesh& mesh_o, const GripperConfig& gripper,
                               const ContactOptions& options) {
  if (mesh_o.triangles.empty()) {
    throw std::invalid_argument("ComputeContactPairs: the mesh has no triangles");
  }
  if (!(options.resolution_m >= 0.001 && options.resolution_m <= 0.1)) {
    throw std::invalid_argument("ComputeContactPairs: resolution_m " +
                                std::to_string(options.resolution_m) +
                                " m is outside [0.001, 0.1]");
  }
  ContactSet set;
  set.resolution_m = options.resolution_m;
  set.max_width_m = gripper.max_aperture_m - 2.0 * gripper.finger_clearance_m;

  // Precompute triangle normals once (a ray may hit the same triangle often).
  std::vector<Eigen::Vector3d> normals(mesh_o.triangles.size());
  for (std::size_t i = 0; i < normals.size(); ++i) normals[i] = mesh_o.TriangleNormal(i);

  const ScenePtr scene = BuildScene(mesh_o);
  const Eigen::Vector3d lo = mesh_o.BoundsMin(), hi = mesh_o.BoundsMax();
  const Eigen::Vector3d extent = hi - lo;
  const double pad = 1e-3 + 1e-3 * extent.maxCoeff();  // start the rays outside the box
  const double min_step = 1e-6 * std::max(1.0, extent.maxCoeff());

  std::vector<Hit> hits;
  std::vector<Contact> entries, exits;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    // Cell centres of the grid on the face spanned by u and v, centred on the box.
    auto grid = [&](int k, std::vector<double>* out) {
      const int n = std::max(1, static_cast<int>(std::floor(extent[k] / options.resolution_m)));
      const double start = lo[k] + 0.5 * (extent[k] - (n - 1) * options.resolution_m);
      out->resize(n);
      for (int i = 0; i < n; ++i) (*out)[i] = start + i * options.resolution_m;
    };
    std::vector<double> us, vs;
    grid(u, &us);
    grid(v, &vs);
    for (double cu : us) {
      for (double cv : vs) {
        Eigen::Vector3d origin;
        origin[axis] = lo[axis] - pad;
        origin[u] = cu;
        origin[v] = cv;
        ++set.rays;
        AllHits(scene.get(), origin, axis, extent[axis] + 2.0 * pad, min_step, &hits);
        if (hits.empty()) continue;
        ++set.rays_hit;
        // Classify: entering when the ray runs against the outward normal.
        entries.clear();
        exits.clear();
        bool valid = hits.size() % 2 == 0;
        for (std::size_t i = 0; valid && i < hits.size(); ++i) {
          const Eigen::Vector3d& n = normals[hits[i].prim];
          const double cos_dir = n[axis];
          const bool entering = cos_dir < 0.0;
          if (std::abs(cos_dir) < kGrazingCos || entering != (i % 2 == 0)) {
            valid = false;
            break;
          }
          Contact c;
          c.p_o = origin;
          c.p_o[axis] += hits[i].t;
          c.n_o = n;
          (entering ? entries : exits).push_back(c);
        }
        if (!valid) {
          ++set.rays_skipped;
          continue;
        }
        // Entry i with exit k >= i: sum_{j=1..F} j pairs for F folds (Eq. 4).
        for (std::size_t i = 0; i < entries.size(); ++i) {
          for (std::size_t k = i; k < exits.size(); ++k) {
            ContactPair pair{entries[i], exits[k], axis};
            if (pair.width_m() <= set.max_width_m) {
              set.pairs.push_back(pair);
            } else {
              ++set.pairs_too_wide;
            }
          }
        }
      }
    }
  }
  return set;
}

bool ContactsClearOfEdges(const TriangleMesh& mesh_o, const ContactPair& pair, double margin_m) {
  if (margin_m <= 0.0) return true;
  constexpr double kToleranceM = 0.005;
  const Eigen::Vector3d along = Eigen::Vector3d::Unit(pair.axis);
  const double a = pair.a.p_o[pair.axis], b = pair.b.p_o[pair.axis];
  const double outside = mesh_o.BoundsMin()[pair.axis] - 0.01;  // the rays start outside the object
  for (int k = 1; k <= 2; ++k) {
    const Eigen::Vector3d across = Eigen::Vector3d::Unit((pair.axis + k) % 3);
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d origin = pair.center_o() + sign * margin_m * across;
      origin[pair.axis] = outside;
      const std::vector<double> hits = IntersectRay(mesh_o, origin, along);
      // From outside a closed mesh the crossings alternate: entry, exit, ...
      bool entry = false, kept = false;
      for (std::size_t i = 0; i < hits.size() && !kept; i += 2) {
        entry = entry || std::abs(origin[pair.axis] + hits[i] - a) < kToleranceM;
        for (std::size_t j = i + 1; entry && j < hits.size() && !kept; j += 2) {
          kept = std::abs(origin[pair.axis] + hits[j] - b) < kToleranceM;
        }
      }
      if (!kept) return false;
    }
  }
  return true;
}

}  // namespace aerograsp
