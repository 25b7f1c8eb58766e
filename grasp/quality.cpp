#include "grasp/quality.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "core/config.h"

namespace aerograsp {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Qhull's error messages go to a per-thread memory stream: a degenerate set
/// is an expected outcome here, not something to print.
FILE* QhullErrorSink() {
  thread_local char buffer[4096];
  thread_local FILE* sink = fmemopen(buffer, sizeof(buffer), "w");
  if (sink) std::rewind(sink);
  return sink;
}

}  // namespace

void FrictionConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "mu", mu, 1e-6, 2.0, "");
  CheckRange(source, prefix + "cone_edges", cone_edges, 3, 16, "");
  CheckRange(source, prefix + "torsional_m", torsional_m, 0.0, 0.05, "m");
}

void AppendContactWrenches(const Eigen::Vector3d& p_o, const Eigen::Vector3d& push_o,
                           const Eigen::Vector3d& com_o, double torque_scale_m,
                           const FrictionConfig& friction, std::vector<Wrench>* wrenches) {
  const Eigen::Vector3d n = push_o.normalized();
  Eigen::Index least;
  n.cwiseAbs().minCoeff(&least);
  const Eigen::Vector3d u = n.cross(Eigen::Vector3d::Unit(least)).normalized();
  const Eigen::Vector3d v = n.cross(u);
  const Eigen::Vector3d r = p_o - com_o;
  const double inv_scale = 1.0 / torque_scale_m;
  for (int j = 0; j < friction.cone_edges; ++j) {
    const double t = 2.0 * kPi * j / friction.cone_edges;
    const Eigen::Vector3d f = n + friction.mu * (std::cos(t) * u + std::sin(t) * v);
    Wrench w;
    w << f, r.cross(f) * inv_scale;
    wrenches->push_back(w);
  }
  if (friction.torsional_m > 0.0) {
    for (double s : {1.0, -1.0}) {
      Wrench w;
      w << n, (r.cross(n) + s * friction.torsional_m * n) * inv_scale;
      wrenches->push_back(w);
    }
  }
}

WrenchQuality ComputeWrenchQuality(const std::vector<Wrench>& wrenches) {
  WrenchQuality quality;
  const int n = static_cast<int>(wrenches.size());
  if (n < 7) return quality;
  // The origin can only be interior when the affine hull is all of R^6.
  Eigen::Matrix<double, 6, Eigen::Dynamic> d(6, n - 1);
  double scale = 0.0;
  for (int i = 1; i < n; ++i) {
    d.col(i - 1) = wrenches[i] - wrenches[0];
    scale = std::max(scale, d.col(i - 1).norm());
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(d);
  lu.setThreshold(1e-9);
  if (scale == 0.0 || lu.rank() < 6) return quality;

  std::vector<coordT> points(6 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 6; ++k) points[6 * i + k] = wrenches[i][k];
  }
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, QhullErrorSink());
  char flags[] = "qhull Qt";
  const int exitcode =
      qh_new_qhull(qh, 6, n, points.data(), False, flags, nullptr, QhullErrorSink());
  if (exitcode == 0) {
    double min_distance = std::numeric_limits<double>::infinity();
    int facets = 0;
    facetT* facet;
    FORALLfacets {
      // Outward normal: points inside satisfy normal . x + offset <= 0, so the
      // origin's distance to the facet's plane is -offset.
      min_distance = std::min(min_distance, -facet->offset);
      ++facets;
    }
    quality.facets = facets;
    const double tolerance = 1e-12 * (1.0 + scale);
    if (facets > 0 && min_distance > tolerance) {
      quality.force_closure = true;
      quality.epsilon = min_distance;
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return quality;
}

std::vector<Wrench> SupportDirections(int count) {
  std::vector<Wrench> dirs;
  dirs.reserve(std::max(count, 12));
  for (int k = 0; k < 6; ++k) {
    for (double s : {1.0, -1.0}) dirs.push_back(s * Wrench::Unit(k));
  }
  std::mt19937 rng(20240611u);  // mt19937's sequence is fixed by the standard
  auto uniform = [&rng]() { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; };
  while (static_cast<int>(dirs.size()) < count) {
    Wrench w;
    for (int k = 0; k < 6; k += 2) {  // Box-Muller: two normals per pair of uniforms
      const double r = std::sqrt(-2.0 * std::log(uniform())), t = 2.0 * kPi * uniform();
      w[k] = r * std::cos(t);
      w[k + 1] = r * std::sin(t);
    }
    if (w.norm() > 1e-9) dirs.push_back(w.normalized());
  }
  return dirs;
}

std::vector<float> SupportTable(const std::vector<Wrench>& wrenches,
                                const std::vector<Wrench>& directions) {
  std::vector<float> table(directions.size());
  for (std::size_t k = 0; k < directions.size(); ++k) {
    double h = -std::numeric_limits<double>::infinity();
    for (const Wrench& w : wrenches) h = std::max(h, directions[k].dot(w));
    table[k] = static_cast<float>(h);
  }
  return table;
}

double EpsilonUpperBound(const float* h_a, const float* h_b, int count) {
  float m = std::numeric_limits<float>::infinity();
  for (int k = 0; k < count; ++k) m = std::min(m, std::max(h_a[k], h_b[k]));
  return m;
}

WeightShare ComputeWeightShare(const Eigen::Vector3d& left_center_o,
                               const Eigen::Vector3d& right_center_o, const Eigen::Vector3d& com_o,
                               const Eigen::Vector3d& g_o, double length_scale_m) {
  const Eigen::Vector3d g = g_o.normalized();
  auto flat = [&g](const Eigen::Vector3d& p) -> Eigen::Vector3d { return p - p.dot(g) * g; };
  const Eigen::Vector3d l = flat(left_center_o), r = flat(right_center_o), c = flat(com_o);
  const Eigen::Vector3d s = r - l;
  WeightShare share;
  if (s.squaredNorm() < 1e-12) {
    share.offset_m = (c - l).norm();
    share.left_share = 0.5;
    return share;  // both grasps on one vertical: nothing stops the object tipping
  }
  const double t = (c - l).dot(s) / s.squaredNorm();
  share.left_share = 1.0 - t;
  share.offset_m = (c - (l + t * s)).norm();
  const double balance = 1.0 - std::abs(2.0 * t - 1.0);
  share.term = std::clamp(balance / (1.0 + share.offset_m / length_scale_m), 0.0, 1.0);
  return share;
}

}  // namespace aerograsp
