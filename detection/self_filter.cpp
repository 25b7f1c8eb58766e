#include "detection/self_filter.h"

#include <algorithm>
#include <cmath>

#include "core/config.h"

namespace aerograsp {
namespace {

/// Points nearer the camera than this are not measured by a depth camera
/// (the D435 sees from about 0.1 m): a shape's part in front of it is cut off.
constexpr double kNearPlaneM = 0.05;

/// Signed distance of p (shape frame) to a box of half extents h: negative inside.
double BoxDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& h) {
  const Eigen::Vector3d q = p.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// Signed distance of p to a cylinder along z of radius r and half length hl.
double CylinderDistance(const Eigen::Vector3d& p, double r, double hl) {
  const Eigen::Vector2d q(p.head<2>().norm() - r, std::abs(p.z()) - hl);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// Half extents of the box around a shape, in its frame.
Eigen::Vector3d HalfExtents(const CollisionShape& shape) {
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      return 0.5 * shape.size;
    case CollisionShape::Type::kCylinder:
      return {shape.size.x(), shape.size.x(), 0.5 * shape.size.y()};
    case CollisionShape::Type::kSphere:
      return Eigen::Vector3d::Constant(shape.size.x());
    case CollisionShape::Type::kMesh:
      break;
  }
  return Eigen::Vector3d::Zero();
}

double SignedDistance(const CollisionShape& shape, const Eigen::Vector3d& p_s) {
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      return BoxDistance(p_s, 0.5 * shape.size);
    case CollisionShape::Type::kCylinder:
      return CylinderDistance(p_s, shape.size.x(), 0.5 * shape.size.y());
    case CollisionShape::Type::kSphere:
      return p_s.norm() - shape.size.x();
    case CollisionShape::Type::kMesh:
      break;
  }
  return 1.0;  // never reached: meshes are left out
}

/// The pixel box [u0, u1) x [v0, v1) covering the part in front of the near
/// plane of the box cMs * [-h, h] (its corners, and where its edges cross the
/// plane); empty when the box lies behind the plane or off the image.
struct PixelRange {
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  bool empty() const { return u1 <= u0 || v1 <= v0; }
};

PixelRange ProjectedBox(const Eigen::Isometry3d& cMs, const Eigen::Vector3d& h,
                        const CameraIntrinsics& K) {
  Eigen::Vector3d corners[8];
  for (int i = 0; i < 8; ++i) {
    corners[i] = cMs * Eigen::Vector3d((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                                       (i & 4) ? h.z() : -h.z());
  }
  double u_min = 1e30, u_max = -1e30, v_min = 1e30, v_max = -1e30;
  bool any = false;
  const auto add = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = K.Project(p);
    u_min = std::min(u_min, uv.x());
    u_max = std::max(u_max, uv.x());
    v_min = std::min(v_min, uv.y());
    v_max = std::max(v_max, uv.y());
    any = true;
  };
  for (const Eigen::Vector3d& p : corners) {
    if (p.z() >= kNearPlaneM) add(p);
  }
  // The 12 edges join corners differing in one bit.
  for (int i = 0; i < 8; ++i) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int j = i | bit;
      if (j == i) continue;
      const Eigen::Vector3d& a = corners[i];
      const Eigen::Vector3d& b = corners[j];
      if ((a.z() < kNearPlaneM) == (b.z() < kNearPlaneM)) continue;
      add(a + (kNearPlaneM - a.z()) / (b.z() - a.z()) * (b - a));
    }
  }
  PixelRange r;
  if (!any) return r;
  // Pixel centres are at integer coordinates.
  r.u0 = static_cast<int>(std::max(0.0, std::floor(u_min)));
  r.v0 = static_cast<int>(std::max(0.0, std::floor(v_min)));
  r.u1 = static_cast<int>(std::min<double>(K.width, std::ceil(u_max) + 1.0));
  r.v1 = static_cast<int>(std::min<double>(K.height, std::ceil(v_max) + 1.0));
  return r;
}

}  // namespace

void SelfFilterOptions::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "margin_m", margin_m, 0.0, 0.1, "m");
}

RobotSelfFilter::RobotSelfFilter(const Platform& platform, const SelfFilterOptions& options)
    : arms_{platform.arm(Side::kLeft), platform.arm(Side::kRight)},
      dMb_{platform.dMb(Side::kLeft), platform.dMb(Side::kRight)},
      options_(options) {
  options_.Validate("self_filter", "");
  for (int a = 0; a < 2; ++a) {
    const std::vector<ArmSegment>& segments = arms_[a].segments();
    for (std::size_t s = 0; s < segments.size(); ++s) {
      for (const CollisionShape& shape : segments[s].collision) {
        if (shape.type == CollisionShape::Type::kMesh) continue;
        shapes_.push_back({a, static_cast<int>(s), shape});
      }
    }
  }
}

SelfFilterResult RobotSelfFilter::Apply(const ArmJointPositions& q_rad,
                                        const Eigen::Isometry3d& dMc, const CameraIntrinsics& K,
                                        double depth_scale_m, DepthImage* depth) const {
  SelfFilterResult result;
  if (!depth || depth->width != K.width || depth->height != K.height || depth->empty() ||
      !(depth_scale_m > 0.0) || !dMc.matrix().allFinite()) {
    return result;
  }
  // The rays of the pixel centres: a point at depth z is (ray_u * z, ray_v * z, z).
  std::vector<double> ray_u(K.width), ray_v(K.height);
  for (int u = 0; u < K.width; ++u) ray_u[u] = (u - K.cx) / K.fx;
  for (int v = 0; v < K.height; ++v) ray_v[v] = (v - K.cy) / K.fy;
  const Eigen::Isometry3d cMd = dMc.inverse();
  const double margin_m = options_.margin_m;
  std::vector<Eigen::Isometry3d> bMs[2];
  for (int a = 0; a < 2; ++a) {
    if (q_rad[a].size() != arms_[a].dof() || !q_rad[a].allFinite()) continue;
    arms_[a].SegmentPoses(q_rad[a], &bMs[a]);
  }
  for (const Shape& s : shapes_) {
    if (bMs[s.side].empty()) continue;
    const Eigen::Isometry3d cMs = cMd * dMb_[s.side] * bMs[s.side][s.segment] * s.shape.segMs;
    const Eigen::Vector3d h = HalfExtents(s.shape) + Eigen::Vector3d::Constant(margin_m);
    const PixelRange box = ProjectedBox(cMs, h, K);
    if (box.empty()) continue;
    ++result.shapes;
    // Pixel points into the shape's frame: p_s = sRc * p_c + s_t.
    const Eigen::Matrix3d sRc = cMs.linear().transpose();
    const Eigen::Vector3d s_t = -(sRc * cMs.translation());
    for (int v = box.v0; v < box.v1; ++v) {
      for (int u = box.u0; u < box.u1; ++u) {
        std::uint16_t& d = depth->at(u, v);
        if (d == 0) continue;
        ++result.tested_pixels;
        const double z = d * depth_scale_m;
        const Eigen::Vector3d p_s = sRc * Eigen::Vector3d(ray_u[u] * z, ray_v[v] * z, z) + s_t;
        if (SignedDistance(s.shape, p_s) <= margin_m) {
          d = 0;
          ++result.dropped_pixels;
        }
      }
    }
  }
  return result;
}

void ArmJointHistory::Add(double t_s, const ArmJointPositions& q_rad) {
  if (!samples_.empty() && t_s < samples_.back().first) return;
  samples_.emplace_back(t_s, q_rad);
  while (samples_.size() > 2 && samples_[1].first < t_s - keep_s_) samples_.pop_front();
}

std::optional<ArmJointPositions> ArmJointHistory::At(double t_s) const {
  if (samples_.empty()) return std::nullopt;
  if (t_s <= samples_.front().first) return samples_.front().second;
  if (t_s >= samples_.back().first) return samples_.back().second;
  const auto after =
      std::upper_bound(samples_.begin(), samples_.end(), t_s,
                       [](double t, const auto& sample) { return t < sample.first; });
  const auto before = std::prev(after);
  const double span_s = after->first - before->first;
  const double w = span_s > 0.0 ? (t_s - before->first) / span_s : 1.0;
  ArmJointPositions q;
  for (int a = 0; a < 2; ++a) {
    const Eigen::VectorXd& q0 = before->second[a];
    const Eigen::VectorXd& q1 = after->second[a];
    q[a] = q0.size() == q1.size() ? Eigen::VectorXd(q0 + w * (q1 - q0)) : q1;
  }
  return q;
}

}  // namespace aerograsp
