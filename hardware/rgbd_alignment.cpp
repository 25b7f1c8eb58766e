#include "hardware/rgbd_alignment.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "hardware/rgbd_camera.h"

namespace aerograsp {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Brown Conrady on normalised coordinates: radial factor, then tangential
/// terms from the undistorted point (OpenCV), or from the radially distorted
/// one (modified).
Eigen::Vector2d BrownConrady(const Eigen::Vector2d& x, const std::array<double, 5>& k,
                             bool modified) {
  const double r2 = x.squaredNorm();
  const double f = 1.0 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
  const Eigen::Vector2d xr = f * x;
  const Eigen::Vector2d t = modified ? xr : x;
  const double p1 = k[2], p2 = k[3];
  return {xr.x() + 2.0 * p1 * t.x() * t.y() + p2 * (r2 + 2.0 * t.x() * t.x()),
          xr.y() + 2.0 * p2 * t.x() * t.y() + p1 * (r2 + 2.0 * t.y() * t.y())};
}

/// Solves map(x) = target by Newton iterations with a finite-difference Jacobian
/// (the lens maps are smooth and close to the identity).
template <typename Map>
Eigen::Vector2d Invert(const Eigen::Vector2d& target, const Map& map) {
  Eigen::Vector2d x = target;
  constexpr double kStep = 1e-7;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d r = map(x) - target;
    if (r.norm() < 1e-12) break;
    Eigen::Matrix2d J;
    J.col(0) = (map(x + Eigen::Vector2d(kStep, 0.0)) - map(x)) / kStep;
    J.col(1) = (map(x + Eigen::Vector2d(0.0, kStep)) - map(x)) / kStep;
    x -= J.inverse() * r;
  }
  return x;
}

}  // namespace

std::string ToString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return "none";
    case DistortionModel::kBrownConrady:
      return "Brown Conrady";
    case DistortionModel::kModifiedBrownConrady:
      return "Modified Brown Conrady";
    case DistortionModel::kInverseBrownConrady:
      return "Inverse Brown Conrady";
  }
  return "none";
}

DistortionModel ParseDistortionModel(const std::string& name, const std::string& source) {
  const std::string n = Lower(name);
  if (n.empty() || n == "none") return DistortionModel::kNone;
  if (n == "brown conrady" || n == "plumb_bob" || n == "radtan")
    return DistortionModel::kBrownConrady;
  if (n == "modified brown conrady") return DistortionModel::kModifiedBrownConrady;
  if (n == "inverse brown conrady") return DistortionModel::kInverseBrownConrady;
  throw HardwareError(source + ": distortion model '" + name +
                      "' is not supported (supported: none, Brown Conrady or plumb_bob, Modified "
                      "Brown Conrady, Inverse Brown Conrady)");
}

bool StreamCalibration::distorted() const {
  return model != DistortionModel::kNone &&
         std::any_of(coeffs.begin(), coeffs.end(), [](double c) { return c != 0.0; });
}

Eigen::Vector2d StreamCalibration::Project(const Eigen::Vector3d& p) const {
  Eigen::Vector2d x(p.x() / p.z(), p.y() / p.z());
  if (distorted()) {
    switch (model) {
      case DistortionModel::kBrownConrady:
      case DistortionModel::kModifiedBrownConrady:
        x = BrownConrady(x, coeffs, model == DistortionModel::kModifiedBrownConrady);
        break;
      case DistortionModel::kInverseBrownConrady:
        x = Invert(x, [this](const Eigen::Vector2d& d) { return BrownConrady(d, coeffs, false); });
        break;
      case DistortionModel::kNone:
        break;
    }
  }
  const CameraIntrinsics& K = intrinsics;
  return {K.fx * x.x() + K.cx, K.fy * x.y() + K.cy};
}

Eigen::Vector3d StreamCalibration::Deproject(double u, double v, double z) const {
  const CameraIntrinsics& K = intrinsics;
  Eigen::Vector2d x((u - K.cx) / K.fx, (v - K.cy) / K.fy);
  if (distorted()) {
    switch (model) {
      case DistortionModel::kBrownConrady:
      case DistortionModel::kModifiedBrownConrady: {
        const bool modified = model == DistortionModel::kModifiedBrownConrady;
        x = Invert(x, [this, modified](const Eigen::Vector2d& p) {
          return BrownConrady(p, coeffs, modified);
        });
        break;
      }
      case DistortionModel::kInverseBrownConrady:
        x = BrownConrady(x, coeffs, false);
        break;
      case DistortionModel::kNone:
        break;
    }
  }
  return {x.x() * z, x.y() * z, z};
}

DepthAligner::DepthAligner(const StreamCalibration& depth_stream,
                           const StreamCalibration& color_stream,
                           const Eigen::Isometry3d& colorMdepth, double depth_scale_m)
    : depth_(depth_stream),
      color_(color_stream),
      t_(colorMdepth.translation()),
      depth_scale_m_(depth_scale_m) {
  // Rays (z = 1 in the depth frame) through every pixel centre and corner of the
  // depth camera, lens model included, turned into the colour frame.
  const CameraIntrinsics& Kd = depth_.intrinsics;
  const Eigen::Matrix3d R = colorMdepth.linear();
  const int cw = Kd.width + 1;
  corner_rays_.resize(static_cast<std::size_t>(cw) * (Kd.height + 1));
  centre_rays_.resize(static_cast<std::size_t>(Kd.width) * Kd.height);
  for (int v = 0; v <= Kd.height; ++v) {
    for (int u = 0; u <= Kd.width; ++u) {
      corner_rays_[std::size_t(v) * cw + u] = R * depth_.Deproject(u - 0.5, v - 0.5, 1.0);
      if (u < Kd.width && v < Kd.height)
        centre_rays_[std::size_t(v) * Kd.width + u] = R * depth_.Deproject(u, v, 1.0);
    }
  }
}

DepthImage AlignDepthToColor(const DepthImage& depth, const StreamCalibration& depth_stream,
                             const StreamCalibration& color_stream,
                             const Eigen::Isometry3d& colorMdepth, double depth_scale_m) {
  return DepthAligner(depth_stream, color_stream, colorMdepth, depth_scale_m).Align(depth);
}

DepthImage DepthAligner::Align(const DepthImage& depth) const {
  const CameraIntrinsics& Kd = depth_.intrinsics;
  const CameraIntrinsics& Kc = color_.intrinsics;
  if (depth.width != Kd.width || depth.height != Kd.height) {
    throw HardwareError("depth alignment: the depth image is " + std::to_string(depth.width) + "x" +
                        std::to_string(depth.height) + ", its intrinsics say " +
                        std::to_string(Kd.width) + "x" + std::to_string(Kd.height));
  }
  const int cw = Kd.width + 1;
  const Eigen::Vector3d& t = t_;
  const double depth_scale_m = depth_scale_m_;
  const StreamCalibration& color_stream = color_;
  const std::vector<Eigen::Vector3d>& corner_rays = corner_rays_;
  const std::vector<Eigen::Vector3d>& centre_rays = centre_rays_;
  constexpr std::uint16_t kNoDepth = std::numeric_limits<std::uint16_t>::max();
  DepthImage out(Kc.width, Kc.height, kNoDepth), cracks(Kc.width, Kc.height, kNoDepth);
  const bool pinhole = !color_stream.distorted();
  for (int v = 0; v < Kd.height; ++v) {
    for (int u = 0; u < Kd.width; ++u) {
      const std::uint16_t d = depth.at(u, v);
      if (d == 0) continue;
      const double z = d * depth_scale_m;
      const Eigen::Vector3d centre = centre_rays[std::size_t(v) * Kd.width + u] * z + t;
      if (centre.z() <= 0.0) continue;
      const double zc_units = std::round(centre.z() / depth_scale_m);
      if (zc_units < 1.0 || zc_units >= kNoDepth) continue;
      const auto zc = static_cast<std::uint16_t>(zc_units);
      // The footprint: bounding box of the pixel's four corners in the colour image.
      double u_min = std::numeric_limits<double>::max(), v_min = u_min;
      double u_max = -u_min, v_max = -u_min;
      bool behind = false;
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector3d p = corner_rays[std::size_t(v + c / 2) * cw + u + c % 2] * z + t;
        if (p.z() <= 0.0) {
          behind = true;
          break;
        }
        const Eigen::Vector2d px =
            pinhole ? Eigen::Vector2d(Kc.fx * p.x() / p.z() + Kc.cx, Kc.fy * p.y() / p.z() + Kc.cy)
                    : color_stream.Project(p);
        u_min = std::min(u_min, px.x()), u_max = std::max(u_max, px.x());
        v_min = std::min(v_min, px.y()), v_max = std::max(v_max, px.y());
      }
      if (behind) continue;
      // Each colour pixel whose centre the footprint covers takes its depth; the
      // pixels only partly covered (the footprint rounded out to whole pixels)
      // fill the cracks neighbours at slightly different depths leave between
      // them, where no footprint covers the centre.
      auto fill = [&](DepthImage* buffer, int u0, int u1, int v0, int v1) {
        u0 = std::max(u0, 0), v0 = std::max(v0, 0);
        u1 = std::min(u1, Kc.width - 1), v1 = std::min(v1, Kc.height - 1);
        for (int y = v0; y <= v1; ++y) {
          std::uint16_t* row = buffer->Row(y);
          for (int x = u0; x <= u1; ++x) row[x] = std::min(row[x], zc);
        }
      };
      fill(&out, static_cast<int>(std::ceil(u_min)), static_cast<int>(std::floor(u_max)),
           static_cast<int>(std::ceil(v_min)), static_cast<int>(std::floor(v_max)));
      fill(&cracks, static_cast<int>(std::lround(u_min)), static_cast<int>(std::lround(u_max)),
           static_cast<int>(std::lround(v_min)), static_cast<int>(std::lround(v_max)));
    }
  }
  for (std::size_t i = 0; i < out.data.size(); ++i) {
    if (out.data[i] == kNoDepth) out.data[i] = cracks.data[i] == kNoDepth ? 0 : cracks.data[i];
  }
  return out;
}

std::vector<int> PairByStamp(const std::vector<double>& color_stamps_s,
                             const std::vector<double>& depth_stamps_s, double max_gap_s) {
  std::vector<int> pairs(color_stamps_s.size(), -1);
  std::size_t j = 0;
  for (std::size_t i = 0; i < color_stamps_s.size(); ++i) {
    const double t = color_stamps_s[i];
    while (j + 1 < depth_stamps_s.size() &&
           std::abs(depth_stamps_s[j + 1] - t) <= std::abs(depth_stamps_s[j] - t))
      ++j;
    if (j < depth_stamps_s.size() && std::abs(depth_stamps_s[j] - t) <= max_gap_s)
      pairs[i] = static_cast<int>(j);
  }
  return pairs;
}

double MedianInterval(const std::vector<double>& stamps_s) {
  if (stamps_s.size() < 2) return std::numeric_limits<double>::infinity();
  std::vector<double> dt;
  for (std::size_t i = 1; i < stamps_s.size(); ++i) dt.push_back(stamps_s[i] - stamps_s[i - 1]);
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

}  // namespace aerograsp
