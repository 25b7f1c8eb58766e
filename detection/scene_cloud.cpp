#include "detection/scene_cloud.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace aerograsp {

PixelBox PixelBox::Clipped(int w, int h) const {
  PixelBox b{std::clamp(x0, 0, w), std::clamp(y0, 0, h), std::clamp(x1, 0, w),
             std::clamp(y1, 0, h)};
  return b;
}

PixelBox PixelBox::Grown(double fraction) const {
  const int dx = static_cast<int>(std::lround(fraction * width()));
  const int dy = static_cast<int>(std::lround(fraction * height()));
  return {x0 - dx, y0 - dy, x1 + dx, y1 + dy};
}

double BoxIoU(const PixelBox& a, const PixelBox& b) {
  if (a.empty() || b.empty()) return 0.0;
  const PixelBox i{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                   std::min(a.y1, b.y1)};
  if (i.empty()) return 0.0;
  const double inter = double(i.width()) * i.height();
  return inter / (double(a.width()) * a.height() + double(b.width()) * b.height() - inter);
}

SceneCloud BuildSceneCloud(const ColorImage& color, const DepthImage& depth, double depth_scale_m,
                           const CameraIntrinsics& K, const PixelBox& box_in,
                           const SceneCloudOptions& options) {
  SceneCloud cloud;
  if (depth.empty() || color.width != depth.width || color.height != depth.height ||
      depth.data.size() != std::size_t(depth.width) * depth.height || !(depth_scale_m > 0.0)) {
    return cloud;
  }
  const PixelBox box = box_in.Clipped(depth.width, depth.height);
  if (box.empty()) return cloud;
  const auto lo =
      static_cast<std::uint32_t>(std::max(1.0, std::ceil(options.min_depth_m / depth_scale_m)));
  const auto hi = static_cast<std::uint32_t>(
      std::min(65535.0, std::floor(options.max_depth_m / depth_scale_m)));
  auto valid = [&](std::uint16_t d) { return d >= lo && d <= hi; };
  for (int y = box.y0; y < box.y1; ++y) {
    const std::uint16_t* row = depth.Row(y);
    for (int x = box.x0; x < box.x1; ++x) cloud.valid_pixels += valid(row[x]) ? 1 : 0;
  }
  if (cloud.valid_pixels == 0) return cloud;
  const int stride =
      std::max(1, static_cast<int>(std::lround(
                      std::sqrt(double(cloud.valid_pixels) / std::max(1, options.target_points)))));
  const std::size_t expected = std::size_t(cloud.valid_pixels) / (stride * stride) + 16;
  cloud.points_c.reserve(expected);
  cloud.normals_c.reserve(expected);
  cloud.colors.reserve(expected);

  const double jump_units = options.max_normal_jump_m / depth_scale_m;
  for (int y = box.y0 + stride / 2; y < box.y1; y += stride) {
    for (int x = box.x0 + stride / 2; x < box.x1; x += stride) {
      const std::uint16_t d = depth.at(x, y);
      if (!valid(d)) continue;
      const double z = d * depth_scale_m;
      const Eigen::Vector3d p = K.Unproject(x, y, z);
      // Plane fit over a 5x5 sample grid spanning about normal_radius_m.
      const int r =
          std::clamp(static_cast<int>(std::lround(options.normal_radius_m * K.fx / z)), 2, 12);
      const int step = std::max(1, r / 2);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
      int count = 0;
      for (int dy = -2 * step; dy <= 2 * step; dy += step) {
        const int yy = y + dy;
        if (yy < 0 || yy >= depth.height) continue;
        for (int dx = -2 * step; dx <= 2 * step; dx += step) {
          const int xx = x + dx;
          if (xx < 0 || xx >= depth.width) continue;
          const std::uint16_t dd = depth.at(xx, yy);
          if (!valid(dd) || std::abs(double(dd) - double(d)) > jump_units) continue;
          const Eigen::Vector3d q =
              K.Unproject(xx, yy, dd * depth_scale_m) - p;  // centred for precision
          sum += q;
          sum2 += q * q.transpose();
          ++count;
        }
      }
      Eigen::Vector3f normal = Eigen::Vector3f::Zero();
      if (count >= 6) {
        const Eigen::Vector3d mean = sum / count;
        const Eigen::Matrix3d cov = sum2 / count - mean * mean.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
        eig.computeDirect(cov);
        Eigen::Vector3d n = eig.eigenvectors().col(0);
        if (n.dot(p) > 0.0) n = -n;
        if (n.allFinite() && eig.eigenvalues()[1] > 1e-12) normal = n.normalized().cast<float>();
      }
      cloud.points_c.push_back(p.cast<float>());
      cloud.normals_c.push_back(normal);
      cloud.colors.push_back(
          Eigen::Vector3f(color.at(x, y, 0), color.at(x, y, 1), color.at(x, y, 2)));
    }
  }
  return cloud;
}

}  // namespace aerograsp
