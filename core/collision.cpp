#include "core/collision.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace aerograsp {
namespace {

using GeometryPtr = std::shared_ptr<fcl::CollisionGeometryd>;

/// An axis-aligned box in the body frame d.
struct Aabb {
  Eigen::Vector3d lo, hi;
};

/// One pre-built FCL shape of an arm segment or of the safe volume.
struct Shape {
  GeometryPtr geometry;
  Eigen::Vector3d half_extents;  ///< of the shape's own bounding box, about its frame's origin (m)
  Eigen::Isometry3d segMs;       ///< shape frame s in its segment (or in d for the safe volume)
  int segment = 0;               ///< index into ArmModel::segments() (0 for the safe volume)
  bool finger = false;           ///< see PlatformCollision::Fingers
};

/// Returns the FCL geometry of a URDF primitive, or nullptr for a mesh.
GeometryPtr MakeGeometry(const CollisionShape& shape, Eigen::Vector3d* half_extents) {
  const Eigen::Vector3d& s = shape.size;
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      *half_extents = 0.5 * s;
      return std::make_shared<fcl::Boxd>(s.x(), s.y(), s.z());
    case CollisionShape::Type::kCylinder:
      *half_extents = Eigen::Vector3d(s.x(), s.x(), 0.5 * s.y());
      return std::make_shared<fcl::Cylinderd>(s.x(), s.y());
    case CollisionShape::Type::kSphere:
      *half_extents = Eigen::Vector3d::Constant(s.x());
      return std::make_shared<fcl::Sphered>(s.x());
    case CollisionShape::Type::kMesh:
      break;
  }
  return nullptr;
}

Aabb BoundsOf(const Eigen::Vector3d& half_extents, const Eigen::Isometry3d& dMs) {
  const Eigen::Vector3d half = dMs.linear().cwiseAbs() * half_extents;
  return {dMs.translation() - half, dMs.translation() + half};
}

/// Distance between two axis-aligned boxes: a lower bound of the distance
/// between any shapes they contain; zero when they overlap.
double Gap(const Aabb& a, const Aabb& b) {
  const Eigen::Vector3d gap = (a.lo - b.hi).cwiseMax(b.lo - a.hi).cwiseMax(0.0);
  return gap.norm();
}

/// Index k of the first joint that is prismatic or whose axis is not collinear
/// with the line from the base origin to its origin; dof() when there is none.
/// Mirrors ArmModel::ShoulderPosition() with the public Jacobian.
int ShoulderJointIndex(const ArmModel& arm) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(arm.dof());
  std::vector<Eigen::Isometry3d> bMs;
  arm.SegmentPoses(zero, &bMs);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> J_b = arm.Jacobian(zero);
  for (int i = 0; i < arm.dof(); ++i) {
    if (arm.joint_type(i) == ArmModel::JointType::kPrismatic) return i;
    const Eigen::Vector3d p = bMs[i + 1].translation();  // segment i + 1 is joint i's frame
    const Eigen::Vector3d axis = J_b.block<3, 1>(3, i);
    if (p.norm() < 1e-12 || axis.cross(p.normalized()).norm() > 1e-6) return i;
  }
  return arm.dof();
}

struct ArmShapes {
  ArmModel arm;
  Eigen::Isometry3d dMb = Eigen::Isometry3d::Identity();
  std::vector<Shape> shapes;
  int exempt_segments = 0;  ///< segments 0 .. exempt_segments - 1 are fixed in place

  bool Exempt(const Shape& s) const { return s.segment < exempt_segments; }

  /// Poses (dMs) and bounds in d of every shape for joint positions q.
  void Place(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* dMs,
             std::vector<Aabb>* bounds) const {
    std::vector<Eigen::Isometry3d> bMseg;
    arm.SegmentPoses(q, &bMseg);
    dMs->resize(shapes.size());
    bounds->resize(shapes.size());
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const Shape& s = shapes[i];
      (*dMs)[i] = dMb * bMseg[s.segment] * s.segMs;
      (*bounds)[i] = BoundsOf(s.half_extents, (*dMs)[i]);
    }
  }
};

ArmShapes BuildArm(const Platform& platform, Side side) {
  ArmShapes a;
  a.arm = platform.arm(side);
  a.dMb = platform.dMb(side);
  a.exempt_segments = ShoulderJointIndex(a.arm) + 1;

  // The tool point in the segment that carries it (the last one), at any q.
  std::vector<Eigen::Isometry3d> bMs;
  a.arm.SegmentPoses(Eigen::VectorXd::Zero(a.arm.dof()), &bMs);
  const int tool_segment = a.arm.dof();
  const Eigen::Isometry3d eMseg = (bMs[tool_segment].inverse() * bMs.back()).inverse();

  const std::vector<ArmSegment>& segments = a.arm.segments();
  for (int seg = 0; seg < static_cast<int>(segments.size()); ++seg) {
    for (const CollisionShape& c : segments[seg].collision) {
      Shape s;
      s.geometry = MakeGeometry(c, &s.half_extents);
      if (!s.geometry) continue;  // URDF meshes are not supported (see the header)
      s.segMs = c.segMs;
      s.segment = seg;
      if (seg == tool_segment) {
        // A finger lies entirely on one side of the approach axis z_e.
        const Eigen::Isometry3d eMs = eMseg * c.segMs;
        const double extent_x = (eMs.linear().cwiseAbs() * s.half_extents).x();
        s.finger = std::abs(eMs.translation().x()) - extent_x > 1e-9;
      }
      a.shapes.push_back(std::move(s));
    }
  }
  return a;
}

/// An object mesh with its hierarchy and, for a closed mesh, its triangles for
/// the inside test.
struct ObjectMesh {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh;
  Eigen::Vector3d center_o, half_o;  ///< bounding box in o (m)
  bool closed = false;
  TriangleMesh solid_o;  ///< the closed mesh's triangles (no colours)
};

/// Ray parity: true when p_o is inside the closed mesh. The ray's direction is
/// oblique to every axis so that it rarely grazes an edge of an axis-aligned
/// mesh; a graze miscounts by one, which the caller accepts.
bool Inside(const ObjectMesh& mesh, const Eigen::Vector3d& p_o) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.5741, 0.6217, 0.5327).normalized();
  return IntersectRay(mesh.solid_o, p_o, dir).size() % 2 == 1;
}

/// Number of contact points FCL reports at most for one pair (box-box gives up
/// to 8); the deepest one gives the penetration depth.
constexpr int kMaxContacts = 8;

/// Distance (m) between two placed shapes that do not touch. FCL's independent
/// GJK solver: libccd's (FCL's default) gets box-box distances wrong by
/// centimetres in some poses (flexible-collision-library/fcl#508; two fingers
/// facing each other hit it).
double Separation(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& dMa,
                  const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& dMb) {
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::DistanceResultd result;
  fcl::distance(&a, dMa, &b, dMb, request, result);
  return result.min_distance;
}

bool Touch(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& dMa,
           const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& dMb) {
  const fcl::CollisionRequestd request;  // one contact, no contact details
  fcl::CollisionResultd result;
  return fcl::collide(&a, dMa, &b, dMb, request, result) > 0;
}

/// Deepest penetration (m, >= 0) among the contacts of a collide() call.
double DeepestContact(const fcl::CollisionResultd& result) {
  double depth = 0.0;
  for (std::size_t i = 0; i < result.numContacts(); ++i) {
    // abs: FCL 0.7's independent EPA reports the depth negated.
    depth = std::max(depth, std::abs(result.getContact(i).penetration_depth));
  }
  return depth;
}

/// Signed distance between two placed shapes (m): minus the penetration depth
/// when they overlap. The depth comes from fcl::collide's contacts (box-box by
/// separating axes; other pairs by the independent solver's EPA, else by
/// libccd's MPR, which overestimates it by up to centimetres), not from FCL's
/// signed distance, whose libccd EPA can throw or never return in touching
/// poses (fcl#493, fcl#578).
double SignedDistance(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& dMa,
                      const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& dMb) {
  if (!Touch(a, dMa, b, dMb)) return Separation(a, dMa, b, dMb);
  for (fcl::GJKSolverType solver : {fcl::GST_INDEP, fcl::GST_LIBCCD}) {
    fcl::CollisionRequestd request(kMaxContacts, /*enable_contact=*/true);
    request.gjk_solver_type = solver;
    fcl::CollisionResultd result;
    if (fcl::collide(&a, dMa, &b, dMb, request, result) > 0) return -DeepestContact(result);
  }
  return 0.0;  // touching, but neither solver found a contact: grazing
}

/// True when the placed shapes are within margin_m of each other.
bool Within(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& dMa,
            const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& dMb, double margin_m) {
  if (Touch(a, dMa, b, dMb)) return true;
  return margin_m > 0.0 && Separation(a, dMa, b, dMb) < margin_m;
}

void CheckMargin(double margin_m) {
  if (!(margin_m >= 0.0) || !std::isfinite(margin_m)) {
    throw std::invalid_argument("PlatformCollision: margin_m is " + std::to_string(margin_m) +
                                "; it must be finite and >= 0 m");
  }
}

}  // namespace

struct PlatformCollision::Impl {
  ArmShapes arms[2];
  std::vector<Shape> volume;  ///< safe volume shapes, segMs = dMs
  std::vector<Aabb> volume_bounds;
  std::vector<ObjectMesh> meshes;

  const ArmShapes& Arm(Side side) const { return arms[static_cast<int>(side)]; }

  /// Throws unless q fits the arm; returns false when q is not finite.
  bool CheckQ(Side side, const Eigen::VectorXd& q) const {
    const ArmModel& arm = Arm(side).arm;
    if (q.size() != arm.dof()) {
      throw std::invalid_argument("PlatformCollision: " + std::string(SideName(side)) +
                                  " arm q has " + std::to_string(q.size()) + " entries; " +
                                  arm.source() + " has " + std::to_string(arm.dof()) + " joints");
    }
    return q.allFinite();
  }
};

PlatformCollision::PlatformCollision(const Platform& platform) : impl_(std::make_unique<Impl>()) {
  for (Side side : kSides) {
    impl_->arms[static_cast<int>(side)] = BuildArm(platform, side);
  }
  for (const CollisionShape& c : platform.safe_volume_d()) {
    Shape s;
    s.geometry = MakeGeometry(c, &s.half_extents);
    if (!s.geometry) continue;
    s.segMs = c.segMs;
    impl_->volume_bounds.push_back(BoundsOf(s.half_extents, s.segMs));
    impl_->volume.push_back(std::move(s));
  }
  if (impl_->volume.empty()) {
    const PlatformConfig& config = platform.config();
    throw std::invalid_argument(config.source + ": vehicle.safe_volume_link: link '" +
                                config.safe_volume_link + "' in " + config.vehicle_urdf +
                                " has no box, cylinder or sphere collision shape (meshes are not "
                                "supported by the collision checker)");
  }
}

PlatformCollision::~PlatformCollision() = default;
PlatformCollision::PlatformCollision(PlatformCollision&&) noexcept = default;
PlatformCollision& PlatformCollision::operator=(PlatformCollision&&) noexcept = default;

int PlatformCollision::ExemptSegmentCount(Side side) const {
  return impl_->Arm(side).exempt_segments;
}

bool PlatformCollision::ArmInSafeVolume(Side side, const Eigen::VectorXd& q,
                                        double margin_m) const {
  CheckMargin(margin_m);
  if (!impl_->CheckQ(side, q)) return true;
  const ArmShapes& a = impl_->Arm(side);
  std::vector<Eigen::Isometry3d> dMs;
  std::vector<Aabb> bounds;
  a.Place(q, &dMs, &bounds);
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    if (a.Exempt(a.shapes[i])) continue;
    for (std::size_t j = 0; j < impl_->volume.size(); ++j) {
      if (Gap(bounds[i], impl_->volume_bounds[j]) > margin_m) continue;
      const Shape& v = impl_->volume[j];
      if (Within(*a.shapes[i].geometry, dMs[i], *v.geometry, v.segMs, margin_m)) return true;
    }
  }
  return false;
}

double PlatformCollision::DistanceToSafeVolume(Side side, const Eigen::VectorXd& q) const {
  if (!impl_->CheckQ(side, q)) return -std::numeric_limits<double>::infinity();
  const ArmShapes& a = impl_->Arm(side);
  std::vector<Eigen::Isometry3d> dMs;
  std::vector<Aabb> bounds;
  a.Place(q, &dMs, &bounds);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    if (a.Exempt(a.shapes[i])) continue;
    for (std::size_t j = 0; j < impl_->volume.size(); ++j) {
      // The bounds' gap is a lower bound of a positive distance only.
      const double lower = Gap(bounds[i], impl_->volume_bounds[j]);
      if (lower > 0.0 && lower >= best) continue;
      const Shape& v = impl_->volume[j];
      best = std::min(best, SignedDistance(*a.shapes[i].geometry, dMs[i], *v.geometry, v.segMs));
    }
  }
  return best;
}

bool PlatformCollision::ArmsCollide(const Eigen::VectorXd& q_left, const Eigen::VectorXd& q_right,
                                    double margin_m) const {
  CheckMargin(margin_m);
  const bool finite_left = impl_->CheckQ(Side::kLeft, q_left);
  if (!impl_->CheckQ(Side::kRight, q_right) || !finite_left) return true;
  const ArmShapes& l = impl_->Arm(Side::kLeft);
  const ArmShapes& r = impl_->Arm(Side::kRight);
  std::vector<Eigen::Isometry3d> dMl, dMr;
  std::vector<Aabb> bounds_l, bounds_r;
  l.Place(q_left, &dMl, &bounds_l);
  r.Place(q_right, &dMr, &bounds_r);
  for (std::size_t i = 0; i < l.shapes.size(); ++i) {
    for (std::size_t j = 0; j < r.shapes.size(); ++j) {
      if (l.Exempt(l.shapes[i]) && r.Exempt(r.shapes[j])) continue;
      if (Gap(bounds_l[i], bounds_r[j]) > margin_m) continue;
      if (Within(*l.shapes[i].geometry, dMl[i], *r.shapes[j].geometry, dMr[j], margin_m)) {
        return true;
      }
    }
  }
  return false;
}

int PlatformCollision::AddMesh(const TriangleMesh& mesh_o) {
  const std::size_t n = mesh_o.vertices.size();
  if (mesh_o.triangles.empty()) {
    throw std::invalid_argument("PlatformCollision::AddMesh: the mesh has no triangles");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh_o.vertices[i].allFinite()) {
      throw std::invalid_argument("PlatformCollision::AddMesh: vertex " + std::to_string(i) +
                                  " is not finite");
    }
  }
  for (std::size_t i = 0; i < mesh_o.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh_o.triangles[i];
    if (t.minCoeff() < 0 || static_cast<std::size_t>(t.maxCoeff()) >= n) {
      throw std::invalid_argument("PlatformCollision::AddMesh: triangle " + std::to_string(i) +
                                  " has an index outside [0, " + std::to_string(n) + ")");
    }
  }

  ObjectMesh m;
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh_o.triangles.size());
  for (const Eigen::Vector3i& t : mesh_o.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  m.bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  m.bvh->beginModel(static_cast<int>(triangles.size()), static_cast<int>(n));
  m.bvh->addSubModel(mesh_o.vertices, triangles);
  m.bvh->endModel();

  const Eigen::Vector3d lo = mesh_o.BoundsMin(), hi = mesh_o.BoundsMax();
  m.center_o = 0.5 * (lo + hi);
  m.half_o = 0.5 * (hi - lo);
  m.closed = CheckMesh(mesh_o).IsClosed();
  if (m.closed) {
    m.solid_o.vertices = mesh_o.vertices;
    m.solid_o.triangles = mesh_o.triangles;
  }
  impl_->meshes.push_back(std::move(m));
  return static_cast<int>(impl_->meshes.size()) - 1;
}

bool PlatformCollision::ArmHitsMesh(Side side, const Eigen::VectorXd& q, int handle,
                                    const Eigen::Isometry3d& dMo, double margin_m,
                                    Fingers fingers) const {
  CheckMargin(margin_m);
  if (handle < 0 || handle >= static_cast<int>(impl_->meshes.size())) {
    throw std::out_of_range("PlatformCollision::ArmHitsMesh: mesh handle " +
                            std::to_string(handle) + " is not one AddMesh returned (there are " +
                            std::to_string(impl_->meshes.size()) + " meshes)");
  }
  if (!impl_->CheckQ(side, q) || !dMo.matrix().allFinite()) return true;
  const ObjectMesh& mesh = impl_->meshes[handle];
  const ArmShapes& a = impl_->Arm(side);
  std::vector<Eigen::Isometry3d> dMs;
  std::vector<Aabb> bounds;
  a.Place(q, &dMs, &bounds);
  const Aabb mesh_bounds = BoundsOf(mesh.half_o, dMo * Eigen::Translation3d(mesh.center_o));
  const Eigen::Isometry3d oMd = dMo.inverse();
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    const Shape& s = a.shapes[i];
    if (fingers == Fingers::kExclude && s.finger) continue;
    if (Gap(bounds[i], mesh_bounds) > margin_m) continue;
    if (Within(*s.geometry, dMs[i], *mesh.bvh, dMo, margin_m)) return true;
    // Not near the surface: the shape is entirely inside or entirely outside.
    if (mesh.closed) {
      const Eigen::Vector3d p_o = oMd * dMs[i].translation();
      if (((p_o - mesh.center_o).cwiseAbs().array() <= mesh.half_o.array()).all() &&
          Inside(mesh, p_o)) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace aerograsp
