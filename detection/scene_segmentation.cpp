#include "detection/scene_segmentation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/config.h"
#include "core/random.h"

namespace aerograsp {
namespace {

/// Points scored per RANSAC sample (strided over the points still in play).
constexpr std::size_t kScoredPoints = 400;
/// cos of the largest angle between a point's normal and its cylinder's, about
/// 25 degrees, and its plane's, 45 degrees (the normals of a far floor are noisy).
constexpr float kNormalCos = 0.9f;
constexpr float kPlaneNormalCos = 0.7f;
/// A cylinder's second point is drawn within this many pixel cells of its first.
constexpr long kSampleCells = 6;
/// Fewest points a piece needs to be a candidate.
constexpr std::size_t kMinPiecePoints = 15;

/// A plane (point and unit normal) or a cylinder (a point on its axis, the unit
/// axis and the radius), fitted to one or two oriented points.
struct Surface {
  bool cylinder = false;
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitZ();  // plane: normal; cylinder: axis
  float radius = 0.0f;

  /// Whether the oriented point p, n lies on the surface: within `tolerance`
  /// (grown with the depth noise at p's depth, `noise_per_m2`: 3 sigma).
  bool Holds(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float tolerance,
             float noise_per_m2) const {
    tolerance = std::max(tolerance, 3.0f * noise_per_m2 * p.z() * p.z());
    if (!cylinder) {
      return std::abs(direction.dot(p - point)) <= tolerance && direction.dot(n) >= kPlaneNormalCos;
    }
    const Eigen::Vector3f v = p - point;
    const Eigen::Vector3f radial = v - v.dot(direction) * direction;
    const float d = radial.norm();
    return std::abs(d - radius) <= tolerance && d > 0.0f && n.dot(radial) >= kNormalCos * d;
  }
};

/// The cylinder whose surface holds both oriented points (normals outwards,
/// towards the camera), if their normals are far enough apart to fix its axis.
bool CylinderThrough(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1,
                     const Eigen::Vector3f& p2, const Eigen::Vector3f& n2, float tolerance,
                     Surface* out) {
  const Eigen::Vector3f cross = n1.cross(n2);
  if (cross.norm() < 0.1f) return false;
  const Eigen::Vector3f axis = cross.normalized();
  // In the plane across the axis both normals' lines meet on the axis.
  const Eigen::Vector3f delta = p2 - axis.dot(p2 - p1) * axis - p1;
  Eigen::Matrix<float, 3, 2> A;
  A.col(0) = n1;
  A.col(1) = -n2;
  const Eigen::Vector2f ts = (A.transpose() * A).ldlt().solve(A.transpose() * delta);
  // The axis lies behind both points (t, s < 0) at about the same distance.
  if (!(ts.x() < 0.0f && ts.y() < 0.0f) || std::abs(ts.x() - ts.y()) > tolerance) return false;
  out->cylinder = true;
  out->point = p1 + ts.x() * n1;
  out->direction = axis;
  out->radius = -0.5f * (ts.x() + ts.y());
  return out->radius > 0.01f && out->radius < 2.0f;
}

/// Twice the largest distance of the points from their centroid, m.
float Spread(const std::vector<Eigen::Vector3f>& points, const std::vector<std::size_t>& members) {
  if (members.empty()) return 0.0f;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (std::size_t i : members) centroid += points[i];
  centroid /= static_cast<float>(members.size());
  float r2 = 0.0f;
  for (std::size_t i : members) r2 = std::max(r2, (points[i] - centroid).squaredNorm());
  return 2.0f * std::sqrt(r2);
}

/// The points by pixel cell (cells of `cell_px` pixels), to find a point's
/// neighbours on the image.
struct CellGrid {
  CellGrid(const std::vector<Eigen::Vector3f>& points, const CameraIntrinsics& K, int cell_px)
      : cols(K.width / cell_px + 1), cell_of(points.size()) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d uv = K.Project(points[i].cast<double>());
      cell_of[i] = static_cast<long>(std::floor(uv.y() / cell_px)) * cols +
                   static_cast<long>(std::floor(uv.x() / cell_px));
      cells[cell_of[i]].push_back(i);
    }
  }
  /// The points of the cell dx, dy cells from point i's (null: none).
  const std::vector<std::size_t>* Near(std::size_t i, long dx, long dy) const {
    const auto it = cells.find(cell_of[i] + dy * cols + dx);
    return it == cells.end() ? nullptr : &it->second;
  }
  long cols;
  std::vector<long> cell_of;
  std::unordered_map<long, std::vector<std::size_t>> cells;
};

/// Union-find over point indices.
struct Pieces {
  explicit Pieces(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t Find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void Join(std::size_t a, std::size_t b) { parent[Find(a)] = Find(b); }
  std::vector<std::size_t> parent;
};

}  // namespace

void SegmentationOptions::Validate(const std::string& source, const std::string& prefix) const {
  const auto require = [&](bool ok, const char* field, const char* what) {
    if (!ok) throw ConfigError(source + ": " + prefix + field + ": " + what);
  };
  require(max_surfaces >= 0 && max_surfaces <= 10, "max_surfaces", "must be in [0, 10] (0: off)");
  require(surface_iterations >= 1 && surface_iterations <= 10000, "surface_iterations",
          "must be in [1, 10000]");
  require(surface_tolerance_m > 0.0 && surface_tolerance_m <= 0.1, "surface_tolerance_m",
          "must be in (0, 0.1] m");
  require(surface_extent >= 1.0 && surface_extent <= 100.0, "surface_extent",
          "must be in [1, 100] (times the object's diameter)");
  require(cluster_gap_m > 0.0 && cluster_gap_m <= 0.5, "cluster_gap_m", "must be in (0, 0.5] m");
  require(max_candidates >= 1 && max_candidates <= 100, "max_candidates", "must be in [1, 100]");
}

std::int64_t SegmentWorkBound(std::size_t points, const SegmentationOptions& options) {
  const std::int64_t n = static_cast<std::int64_t>(points);
  const std::int64_t scored = std::min<std::int64_t>(n, kScoredPoints);
  // Each surface: its samples (a plane and a cylinder each) on the scored
  // points, then every point against the best. Then the pieces: each point
  // projected (twice: all and those off the surfaces) and tested against the
  // neighbours of its 3 x 3 cells.
  return options.max_surfaces * (options.surface_iterations * 2 * scored + n) + 11 * n;
}

SceneSegments SegmentScene(const SceneCloud& scene, const CameraIntrinsics& K,
                           double object_diameter_m, double object_radius_m, double depth_behind_m,
                           double depth_noise_per_m2, const SegmentationOptions& options) {
  SceneSegments out;
  const std::vector<Eigen::Vector3f>& points = scene.points_c;
  const std::vector<Eigen::Vector3f>& normals = scene.normals_c;
  const float tolerance = static_cast<float>(options.surface_tolerance_m);
  const float noise = static_cast<float>(depth_noise_per_m2);
  const float large_m = static_cast<float>(options.surface_extent * object_diameter_m);

  // The points still in play: those with a normal, off every large surface so far.
  std::vector<std::size_t> left;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!normals[i].isZero()) left.push_back(i);
  }
  // The cloud's pixel stride (it samples the image on a grid).
  const double stride_px =
      std::max(1.0, std::sqrt(static_cast<double>(std::max(scene.valid_pixels, 1)) /
                              static_cast<double>(std::max<std::size_t>(points.size(), 1))));
  const int cell_px = std::max(1, static_cast<int>(std::ceil(stride_px)));
  if (K.width <= 0 || K.height <= 0) return out;
  const CellGrid grid(points, K, cell_px);
  std::vector<bool> in_play(points.size(), false);
  for (std::size_t i : left) in_play[i] = true;
  FastRandom rng(options.seed);
  for (int round = 0; round < options.max_surfaces && left.size() >= 2 * kMinPiecePoints; ++round) {
    const std::size_t stride = std::max<std::size_t>(1, left.size() / kScoredPoints);
    const auto count = [&](const Surface& s) {
      int held = 0;
      for (std::size_t k = 0; k < left.size(); k += stride) {
        const std::size_t i = left[k];
        held += s.Holds(points[i], normals[i], tolerance, noise);
      }
      return held;
    };
    Surface best;
    int best_held = 0;
    for (int it = 0; it < options.surface_iterations; ++it) {
      // The second point near the first on the image (likely the same surface).
      const std::size_t a = left[rng.Next() % left.size()];
      const long dx = static_cast<long>(rng.Next() % (2 * kSampleCells + 1)) - kSampleCells;
      const long dy = static_cast<long>(rng.Next() % (2 * kSampleCells + 1)) - kSampleCells;
      const std::vector<std::size_t>* cell = grid.Near(a, dx, dy);
      std::size_t b = a;
      if (cell && !cell->empty()) b = (*cell)[rng.Next() % cell->size()];
      if (!in_play[b]) b = a;
      Surface plane;
      plane.point = points[a];
      plane.direction = normals[a];
      const int plane_held = count(plane);
      if (plane_held > best_held) {
        best_held = plane_held;
        best = plane;
      }
      Surface cylinder;
      if (a != b &&
          CylinderThrough(points[a], normals[a], points[b], normals[b], tolerance, &cylinder)) {
        const int cylinder_held = count(cylinder);
        if (cylinder_held > best_held) {
          best_held = cylinder_held;
          best = cylinder;
        }
      }
    }
    if (best_held == 0) break;
    std::vector<std::size_t> on, off;
    for (std::size_t i : left)
      (best.Holds(points[i], normals[i], tolerance, noise) ? on : off).push_back(i);
    // Not much larger than the object: it may be the object's own face; stop.
    if (Spread(points, on) <= large_m) break;
    for (std::size_t i : on) in_play[i] = false;
    left = std::move(off);
    ++out.surfaces;
  }

  for (std::size_t i : left) {
    out.foreground.points_c.push_back(points[i]);
    out.foreground.normals_c.push_back(normals[i]);
    out.foreground.colors.push_back(i < scene.colors.size() ? scene.colors[i]
                                                            : Eigen::Vector3f::Zero());
  }
  out.foreground.valid_pixels = static_cast<int>(out.foreground.points_c.size());

  // Pieces: neighbours on the pixel grid (cells of the cloud's pixel stride)
  // nearer than the gap at their depth.
  const std::vector<Eigen::Vector3f>& fg = out.foreground.points_c;
  if (fg.empty()) return out;
  const auto gap = [&](float z) {
    return static_cast<float>(std::max(options.cluster_gap_m, 2.5 * stride_px * z / K.fx));
  };
  const CellGrid fg_grid(fg, K, cell_px);
  Pieces pieces(fg.size());
  for (std::size_t i = 0; i < fg.size(); ++i) {
    const float g = gap(fg[i].z());
    for (long dy = -1; dy <= 1; ++dy) {
      for (long dx = -1; dx <= 1; ++dx) {
        const std::vector<std::size_t>* cell = fg_grid.Near(i, dx, dy);
        if (!cell) continue;
        for (std::size_t j : *cell) {
          if (j > i && (fg[i] - fg[j]).squaredNorm() <= g * g) pieces.Join(i, j);
        }
      }
    }
  }
  std::unordered_map<std::size_t, std::vector<std::size_t>> members;
  for (std::size_t i = 0; i < fg.size(); ++i) members[pieces.Find(i)].push_back(i);
  // Each piece as a ball (centroid, radius, points), a fixed order: most points first.
  struct Ball {
    Eigen::Vector3d centre;
    double radius;
    std::size_t points;
  };
  std::vector<Ball> balls;
  for (const auto& [root, m] : members) {
    if (m.size() < kMinPiecePoints / 3) continue;  // a speck
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t i : m) c += fg[i].cast<double>();
    c /= static_cast<double>(m.size());
    balls.push_back({c, 0.5 * Spread(fg, m), m.size()});
  }
  std::sort(balls.begin(), balls.end(), [](const Ball& a, const Ball& b) {
    return a.points != b.points ? a.points > b.points : a.centre.norm() < b.centre.norm();
  });
  // The candidates: each piece that fits in the object's bounding sphere, and
  // the group of it and the pieces nearest to it that still fit (an object
  // whose parts the pixel grid sees apart: the arms of a U behind its base).
  const double fits_m = 1.2 * object_radius_m;
  std::vector<Ball> candidates;
  for (std::size_t i = 0; i < balls.size(); ++i) {
    if (balls[i].radius > fits_m) continue;
    if (balls[i].points >= kMinPiecePoints) candidates.push_back(balls[i]);
    std::vector<std::size_t> others;
    for (std::size_t j = 0; j < balls.size(); ++j) {
      if (j != i && balls[j].radius <= fits_m) others.push_back(j);
    }
    std::stable_sort(others.begin(), others.end(), [&](std::size_t a, std::size_t b) {
      return (balls[a].centre - balls[i].centre).norm() <
             (balls[b].centre - balls[i].centre).norm();
    });
    std::vector<std::size_t> group{i};
    Ball joined = balls[i];
    for (std::size_t j : others) {
      const std::size_t points = joined.points + balls[j].points;
      const Eigen::Vector3d centre =
          (joined.centre * joined.points + balls[j].centre * balls[j].points) / points;
      double radius = 0.0;
      group.push_back(j);
      for (std::size_t k : group)
        radius = std::max(radius, (balls[k].centre - centre).norm() + balls[k].radius);
      if (radius > fits_m) {
        group.pop_back();
        continue;
      }
      joined = {centre, radius, points};
    }
    if (group.size() > 1 && joined.points >= kMinPiecePoints) candidates.push_back(joined);
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Ball& a, const Ball& b) { return a.points > b.points; });
  for (const Ball& b : candidates) {
    if (static_cast<int>(out.centres_c.size()) >= options.max_candidates) break;
    const Eigen::Vector3d c = b.centre + b.centre.normalized() * depth_behind_m;
    // A group found again from another of its pieces.
    bool seen = false;
    for (const Eigen::Vector3d& e : out.centres_c) seen = seen || (e - c).norm() < 1e-6;
    if (!seen) out.centres_c.push_back(c);
  }
  return out;
}

}  // namespace aerograsp
