// Rotational symmetry of a mesh: candidate rotations from the principal axes
// and from the farthest vertices, each verified by the distance of rotated
// surface points to the surface (a grid of triangles answers "is there a
// triangle within the tolerance"), then closed under composition.
#include "core/symmetry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/config.h"
#include "core/random.h"

namespace aerograsp {
namespace {

using Vec3 = Eigen::Vector3d;

/// The point of triangle (a, b, c) nearest p, with its barycentric weights
/// (Voronoi regions of the vertices, then the edges, then the face).
Vec3 ClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* weights) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *weights = Vec3(1, 0, 0);
    return a;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *weights = Vec3(0, 1, 0);
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    *weights = Vec3(1 - v, v, 0);
    return a + v * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *weights = Vec3(0, 0, 1);
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    *weights = Vec3(1 - w, 0, w);
    return a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    *weights = Vec3(0, 1 - w, w);
    return b + w * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  *weights = Vec3(1 - v - w, v, w);
  return a + v * ab + w * ac;
}

/// The triangles near each cell of a grid over the mesh: every triangle within
/// `tolerance` of a point is listed in the point's cell.
class SurfaceGrid {
 public:
  SurfaceGrid(const TriangleMesh& mesh, double tolerance) : mesh_(mesh), tolerance_(tolerance) {
    const Vec3 lo = mesh.BoundsMin(), hi = mesh.BoundsMax();
    const double diagonal = (hi - lo).norm();
    cell_ = std::max(diagonal / 32.0, 4.0 * tolerance);
    origin_ = lo - Vec3::Constant(tolerance + 0.5 * cell_);
    size_ = (((hi - lo).array() + 2.0 * tolerance + cell_) / cell_).ceil().cast<int>().max(1);
    cells_.resize(static_cast<std::size_t>(size_.prod()));
    normals_.resize(mesh.triangles.size(), Vec3::Zero());
    const double half_diagonal = 0.5 * std::sqrt(3.0) * cell_;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Vec3 normal = mesh.TriangleNormal(t);
      if (normal.isZero()) continue;  // no area: no surface to land on
      normals_[t] = normal;
      const Vec3& a = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][0])];
      const Vec3& b = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][1])];
      const Vec3& c = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][2])];
      const Eigen::Array3i from = Cell(a.cwiseMin(b).cwiseMin(c) - Vec3::Constant(tolerance));
      const Eigen::Array3i to = Cell(a.cwiseMax(b).cwiseMax(c) + Vec3::Constant(tolerance));
      for (int z = from.z(); z <= to.z(); ++z) {
        for (int y = from.y(); y <= to.y(); ++y) {
          for (int x = from.x(); x <= to.x(); ++x) {
            const Vec3 centre = origin_ + cell_ * Vec3(x + 0.5, y + 0.5, z + 0.5);
            if (std::abs(normal.dot(centre - a)) > half_diagonal + tolerance) continue;
            cells_[Index(x, y, z)].push_back(static_cast<std::uint32_t>(t));
          }
        }
      }
    }
  }

  /// The nearest triangle within the tolerance of p (-1 if none), its
  /// barycentric weights at the nearest point.
  int Nearest(const Vec3& p, Vec3* weights) const {
    const Vec3 g = (p - origin_) / cell_;
    if ((g.array() < 0.0).any() || (g.array() >= size_.cast<double>()).any()) return -1;
    const Eigen::Array3i i = g.array().floor().cast<int>();
    int best = -1;
    double best2 = tolerance_ * tolerance_;
    Vec3 w;
    for (const std::uint32_t t : cells_[Index(i.x(), i.y(), i.z())]) {
      const Eigen::Vector3i& tri = mesh_.triangles[t];
      const Vec3 q = ClosestOnTriangle(p, mesh_.vertices[static_cast<std::size_t>(tri[0])],
                                       mesh_.vertices[static_cast<std::size_t>(tri[1])],
                                       mesh_.vertices[static_cast<std::size_t>(tri[2])], &w);
      const double d2 = (q - p).squaredNorm();
      if (d2 <= best2) {
        best2 = d2;
        best = static_cast<int>(t);
        *weights = w;
      }
    }
    return best;
  }

  const Vec3& normal(int t) const { return normals_[static_cast<std::size_t>(t)]; }

 private:
  Eigen::Array3i Cell(const Vec3& p) const {
    return ((p - origin_) / cell_).array().floor().cast<int>().max(0).min(size_ - 1);
  }
  std::size_t Index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(size_.y()) +
            static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(size_.x()) +
           static_cast<std::size_t>(x);
  }

  const TriangleMesh& mesh_;
  double tolerance_;
  double cell_ = 1.0;
  Vec3 origin_ = Vec3::Zero();
  Eigen::Array3i size_ = Eigen::Array3i::Ones();
  std::vector<std::vector<std::uint32_t>> cells_;
  std::vector<Vec3> normals_;
};

/// A point on the surface: a vertex (no normal) or an area sample.
struct SurfacePoint {
  Vec3 p;
  Vec3 normal = Vec3::Zero();  ///< zero for a vertex (its normal is not defined)
  Vec3 color = Vec3::Zero();   ///< RGB 0..255 when the mesh has colours
  /// Its colour is compared: a vertex, or a sample of a triangle whose corners
  /// agree in colour (across a colour seam the interpolated colour depends on
  /// how the quad was split, which a symmetry need not preserve).
  bool compare_color = true;
};

constexpr double kColorTolerance = 60.0;  // RGB distance of one colour, 0..255 units

/// The colour of corner k of triangle t.
Vec3 Corner(const TriangleMesh& mesh, int t, int k) {
  const auto& c =
      mesh.colors[static_cast<std::size_t>(mesh.triangles[static_cast<std::size_t>(t)][k])];
  return Vec3(c[0], c[1], c[2]);
}

Vec3 ColorAt(const TriangleMesh& mesh, int t, const Vec3& w) {
  Vec3 color = Vec3::Zero();
  const Eigen::Vector3i& tri = mesh.triangles[static_cast<std::size_t>(t)];
  for (int k = 0; k < 3; ++k) {
    const auto& c = mesh.colors[static_cast<std::size_t>(tri[k])];
    color += w[k] * Vec3(c[0], c[1], c[2]);
  }
  return color;
}

class SymmetryTester {
 public:
  SymmetryTester(const TriangleMesh& mesh, const SymmetryOptions& options, const Vec3& center,
                 double tolerance)
      : mesh_(mesh),
        grid_(mesh, tolerance),
        center_(center),
        colored_(!mesh.colors.empty() && mesh.colors.size() == mesh.vertices.size()) {
    // Vertices (evenly spread when there are many) and area-weighted samples.
    const std::size_t nv = mesh.vertices.size();
    const std::size_t step =
        std::max<std::size_t>(1, nv / static_cast<std::size_t>(std::max(1, options.max_vertices)));
    std::vector<SurfacePoint> vertices, samples;
    if (options.max_vertices > 0) {
      for (std::size_t v = 0; v < nv; v += step) {
        SurfacePoint s;
        s.p = mesh.vertices[v];
        if (colored_) s.color = Vec3(mesh.colors[v][0], mesh.colors[v][1], mesh.colors[v][2]);
        vertices.push_back(s);
      }
    }
    std::vector<double> cumulative(mesh.triangles.size(), 0.0);
    double area = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Eigen::Vector3i& tri = mesh.triangles[t];
      area += 0.5 * (mesh.vertices[static_cast<std::size_t>(tri[1])] -
                     mesh.vertices[static_cast<std::size_t>(tri[0])])
                        .cross(mesh.vertices[static_cast<std::size_t>(tri[2])] -
                               mesh.vertices[static_cast<std::size_t>(tri[0])])
                        .norm();
      cumulative[t] = area;
    }
    FastRandom rng(options.seed);
    for (int k = 0; k < options.surface_samples; ++k) {
      const double pick = rng.Uniform(0.0, area);
      const std::size_t t = std::min<std::size_t>(
          mesh.triangles.size() - 1,
          static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), pick) -
                                   cumulative.begin()));
      double a = rng.Uniform(), b = rng.Uniform();
      if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
      }
      const Vec3 w(1.0 - a - b, a, b);
      const Eigen::Vector3i& tri = mesh.triangles[t];
      SurfacePoint s;
      s.p = w[0] * mesh.vertices[static_cast<std::size_t>(tri[0])] +
            w[1] * mesh.vertices[static_cast<std::size_t>(tri[1])] +
            w[2] * mesh.vertices[static_cast<std::size_t>(tri[2])];
      s.normal = mesh.TriangleNormal(t);
      if (s.normal.isZero()) continue;
      if (colored_) {
        s.color = ColorAt(mesh, static_cast<int>(t), w);
        for (int k = 0; k < 3; ++k) {
          s.compare_color = s.compare_color && (Corner(mesh, static_cast<int>(t), k) -
                                                Corner(mesh, static_cast<int>(t), (k + 1) % 3))
                                                       .norm() < kColorTolerance;
        }
      }
      samples.push_back(s);
    }
    // Interleaved, so that a wrong rotation fails within the first few points.
    for (std::size_t i = 0; i < std::max(vertices.size(), samples.size()); ++i) {
      if (i < vertices.size()) points_.push_back(vertices[i]);
      if (i < samples.size()) points_.push_back(samples[i]);
    }
    allowed_failures_ = static_cast<std::size_t>(options.max_outlier_fraction *
                                                 static_cast<double>(points_.size()));
  }

  bool IsSymmetry(const Eigen::Matrix3d& R) const {
    std::size_t failures = 0;
    Vec3 w;
    for (const SurfacePoint& s : points_) {
      const Vec3 q = center_ + R * (s.p - center_);
      const int t = grid_.Nearest(q, &w);
      bool ok = t >= 0;
      if (ok && !s.normal.isZero()) ok = (R * s.normal).dot(grid_.normal(t)) > 0.5;
      if (ok && colored_ && s.compare_color) {
        // The colour there, or one of its triangle's corners' (near a seam).
        double best = (ColorAt(mesh_, t, w) - s.color).norm();
        for (int k = 0; k < 3; ++k) best = std::min(best, (Corner(mesh_, t, k) - s.color).norm());
        ok = best < kColorTolerance;
      }
      if (!ok && ++failures > allowed_failures_) return false;
    }
    return true;
  }

 private:
  const TriangleMesh& mesh_;
  SurfaceGrid grid_;
  Vec3 center_;
  bool colored_;
  std::vector<SurfacePoint> points_;
  std::size_t allowed_failures_ = 0;
};

/// Orthonormal frame whose first axis is along x and second in the (x, y) plane.
Eigen::Matrix3d Frame(const Vec3& x, const Vec3& y) {
  Eigen::Matrix3d F;
  F.col(0) = x.normalized();
  F.col(1) = (y - y.dot(F.col(0)) * F.col(0)).normalized();
  F.col(2) = F.col(0).cross(F.col(1));
  return F;
}

/// A signed permutation when the rotation is one to rounding; re-orthonormalised otherwise.
Eigen::Matrix3d Tidy(const Eigen::Matrix3d& R) {
  Eigen::Matrix3d rounded = R.array().round().matrix();
  if ((R - rounded).cwiseAbs().maxCoeff() < 1e-6) return rounded;
  return Eigen::Quaterniond(R).normalized().toRotationMatrix();
}

bool Contains(const std::vector<Eigen::Matrix3d>& set, const Eigen::Matrix3d& R) {
  for (const Eigen::Matrix3d& S : set) {
    if ((S - R).cwiseAbs().maxCoeff() < 1e-3) return true;
  }
  return false;
}

double AngleOf(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0));
}

}  // namespace

void SymmetryOptions::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "tolerance_ratio", tolerance_ratio, 1e-6, 0.05, "");
  CheckRange(source, prefix + "surface_samples", surface_samples, 100, 100000, "");
  CheckRange(source, prefix + "max_vertices", max_vertices, 0, 100000, "");
  CheckRange(source, prefix + "max_outlier_fraction", max_outlier_fraction, 0.0, 0.2, "");
  CheckRange(source, prefix + "max_axis_order", max_axis_order, 2, 1000, "");
}

ObjectSymmetry FindMeshSymmetries(const TriangleMesh& mesh, const SymmetryOptions& options) {
  options.Validate("symmetry options", "symmetry.");
  // Area centroid and second moment of the surface about it (per triangle:
  // A/12 (s s^T + a a^T + b b^T + c c^T), s = a + b + c).
  double area = 0.0;
  Vec3 first = Vec3::Zero();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices.at(static_cast<std::size_t>(tri[0]));
    const Vec3& b = mesh.vertices.at(static_cast<std::size_t>(tri[1]));
    const Vec3& c = mesh.vertices.at(static_cast<std::size_t>(tri[2]));
    const double A = 0.5 * (b - a).cross(c - a).norm();
    area += A;
    first += A * (a + b + c) / 3.0;
  }
  if (!(area > 0.0)) throw std::invalid_argument("FindMeshSymmetries: the mesh has no area");
  ObjectSymmetry symmetry;
  const Vec3 center = first / area;
  symmetry.center_o = center;
  symmetry.rotations.push_back(Eigen::Matrix3d::Identity());
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3i& tri : mesh.triangles) {
    const Vec3 a = mesh.vertices[static_cast<std::size_t>(tri[0])] - center;
    const Vec3 b = mesh.vertices[static_cast<std::size_t>(tri[1])] - center;
    const Vec3 c = mesh.vertices[static_cast<std::size_t>(tri[2])] - center;
    const double A = 0.5 * (b - a).cross(c - a).norm();
    const Vec3 s = a + b + c;
    second +=
        A / 12.0 * (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(second);
  const Eigen::Matrix3d axes = eigen.eigenvectors();
  const Eigen::Vector3d moments = eigen.eigenvalues();

  const double tolerance = options.tolerance_ratio * (mesh.BoundsMax() - mesh.BoundsMin()).norm();
  const SymmetryTester tester(mesh, options, center, tolerance);

  // A continuous axis: a principal axis about which two unrelated angles are
  // symmetries. The axis whose moment stands out most from the others first.
  std::vector<int> order = {0, 1, 2};
  const auto distinctness = [&moments](int k) {
    return std::min(std::abs(moments[k] - moments[(k + 1) % 3]),
                    std::abs(moments[k] - moments[(k + 2) % 3]));
  };
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return distinctness(a) > distinctness(b); });
  for (const int k : order) {
    const Vec3 axis = axes.col(k);
    if (tester.IsSymmetry(Eigen::AngleAxisd(0.61, axis).toRotationMatrix()) &&
        tester.IsSymmetry(Eigen::AngleAxisd(1.93, axis).toRotationMatrix())) {
      Vec3 a = axis;
      // The sign that points along the larger coordinate (a stable, readable axis).
      Eigen::Index largest = 0;
      a.cwiseAbs().maxCoeff(&largest);
      if (a[largest] < 0.0) a = -a;
      if ((a - a.array().round().matrix()).cwiseAbs().maxCoeff() < 1e-6) a = a.array().round();
      symmetry.continuous_axis_o = a;
      const Eigen::Matrix3d half =
          Tidy(Eigen::AngleAxisd(M_PI, axes.col((k + 1) % 3)).toRotationMatrix());
      if (tester.IsSymmetry(half)) symmetry.rotations.push_back(half);
      return symmetry;
    }
  }

  std::vector<Eigen::Matrix3d>& found = symmetry.rotations;
  const auto consider = [&](const Eigen::Matrix3d& R) {
    const Eigen::Matrix3d tidy = Tidy(R);
    if (!Contains(found, tidy) && tester.IsSymmetry(tidy)) found.push_back(tidy);
  };
  // Turns 2 pi / n about each principal axis.
  for (int k = 0; k < 3; ++k) {
    for (int n = 2; n <= options.max_axis_order; ++n) {
      consider(Eigen::AngleAxisd(2.0 * M_PI / n, axes.col(k)).toRotationMatrix());
    }
  }
  // Rotations taking the farthest vertex p1 and the farthest vertex p2 off its
  // line through the centre onto vertices at the same distances from the
  // centre and from each other.
  std::vector<double> radius(mesh.vertices.size());
  std::size_t p1 = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    radius[v] = (mesh.vertices[v] - center).norm();
    if (radius[v] > radius[p1]) p1 = v;
  }
  const Vec3 d1 = mesh.vertices[p1] - center;
  std::size_t p2 = p1;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3 d = mesh.vertices[v] - center;
    if (d.cross(d1).norm() > std::sin(5.0 * M_PI / 180.0) * d.norm() * d1.norm() &&
        (p2 == p1 || radius[v] > radius[p2])) {
      p2 = v;
    }
  }
  if (p2 != p1) {
    const Vec3 d2 = mesh.vertices[p2] - center;
    const Eigen::Matrix3d from = Frame(d1, d2);
    const double gap = (d1 - d2).norm();
    std::vector<std::size_t> ring1, ring2;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (std::abs(radius[v] - radius[p1]) <= tolerance) ring1.push_back(v);
      if (std::abs(radius[v] - radius[p2]) <= tolerance) ring2.push_back(v);
    }
    constexpr std::size_t kMaxPairs = 200000;  // bounds the time on a many-vertex sphere
    if (ring1.size() * ring2.size() <= kMaxPairs) {
      for (const std::size_t q1 : ring1) {
        for (const std::size_t q2 : ring2) {
          const Vec3 e1 = mesh.vertices[q1] - center, e2 = mesh.vertices[q2] - center;
          if (q1 == q2 || std::abs((e1 - e2).norm() - gap) > 2.0 * tolerance) continue;
          if (e1.cross(e2).norm() <= 1e-12) continue;
          consider(Frame(e1, e2) * from.transpose());
        }
      }
    }
  }
  // Closed under composition (products of symmetries are symmetries).
  constexpr std::size_t kMaxGroup = 240;
  for (bool grew = true; grew && found.size() <= kMaxGroup;) {
    grew = false;
    const std::size_t n = found.size();
    for (std::size_t i = 1; i < n; ++i) {
      for (std::size_t j = 1; j < n; ++j) {
        const Eigen::Matrix3d product = Tidy(found[i] * found[j]);
        if (!Contains(found, product)) {
          found.push_back(product);
          grew = true;
        }
      }
    }
  }
  // A stable order: by angle, then by axis.
  std::stable_sort(found.begin() + 1, found.end(),
                   [](const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
                     const double ta = AngleOf(a), tb = AngleOf(b);
                     if (std::abs(ta - tb) > 1e-6) return ta < tb;
                     const Eigen::AngleAxisd aa(a), ab(b);
                     for (int k = 0; k < 3; ++k) {
                       if (std::abs(aa.axis()[k] - ab.axis()[k]) > 1e-6)
                         return aa.axis()[k] > ab.axis()[k];
                     }
                     return false;
                   });
  return symmetry;
}

Eigen::Isometry3d WithSymmetricRotation(const Eigen::Isometry3d& xMo, const Eigen::Matrix3d& xRo,
                                        const ObjectSymmetry& symmetry) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = xRo;
  result.translation() = xMo * symmetry.center_o - xRo * symmetry.center_o;
  return result;
}

std::string DescribeSymmetry(const ObjectSymmetry& symmetry) {
  std::ostringstream out;
  out.precision(3);
  const auto vec = [&out](const Vec3& v) {
    out << "(" << (std::abs(v.x()) < 5e-4 ? 0.0 : v.x()) << ", "
        << (std::abs(v.y()) < 5e-4 ? 0.0 : v.y()) << ", " << (std::abs(v.z()) < 5e-4 ? 0.0 : v.z())
        << ")";
  };
  if (symmetry.continuous_axis_o) {
    out << "continuous about the axis ";
    vec(*symmetry.continuous_axis_o);
    out << " through ";
    vec(symmetry.center_o);
    out << (symmetry.rotations.size() > 1 ? ", and a half turn across it"
                                          : ", no half turn across it");
    return out.str();
  }
  const std::size_t n = symmetry.rotations.size();
  if (n <= 1) return "none (the identity only)";
  // The axes (up to sign) and their orders (2 pi / the smallest angle about each).
  std::vector<std::pair<Vec3, int>> axes;
  for (std::size_t i = 1; i < n; ++i) {
    const Eigen::AngleAxisd aa(symmetry.rotations[i]);
    Vec3 axis = aa.axis();
    Eigen::Index largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis[largest] < 0.0) axis = -axis;
    const double angle = std::min(aa.angle(), 2.0 * M_PI - aa.angle());
    const int order = static_cast<int>(std::lround(2.0 * M_PI / angle));
    bool known = false;
    for (auto& entry : axes) {
      if (entry.first.cross(axis).norm() < 1e-3) {
        entry.second = std::max(entry.second, order);
        known = true;
      }
    }
    if (!known) axes.emplace_back(axis, order);
  }
  out << n << " rotations";
  if (n == 24) out << " (a cube's group)";
  if (n == 12 && axes.size() == 7) out << " (a regular tetrahedron's group)";
  if (n == 60) out << " (a regular icosahedron's group)";
  out << ": ";
  if (axes.size() <= 4) {
    for (std::size_t i = 0; i < axes.size(); ++i) {
      out << (i ? ", " : "") << axes[i].second << "-fold about ";
      vec(axes[i].first);
    }
  } else {
    std::vector<int> counts(13, 0);
    for (const auto& entry : axes) ++counts[static_cast<std::size_t>(std::min(entry.second, 12))];
    bool first = true;
    for (int order = 12; order >= 2; --order) {
      if (counts[static_cast<std::size_t>(order)] == 0) continue;
      out << (first ? "" : ", ") << counts[static_cast<std::size_t>(order)] << " " << order
          << "-fold axes";
      first = false;
    }
  }
  out << " through ";
  vec(symmetry.center_o);
  return out.str();
}

}  // namespace aerograsp
