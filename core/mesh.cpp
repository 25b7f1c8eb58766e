// Triangle meshes: loading (dispatch by extension and the checks every format
// shares), checking, and mass properties. The format readers and the PLY writer
// are in mesh_formats.cpp.
#include "core/mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh_formats.h"

namespace aerograsp {

using mesh_formats::Fail;
using mesh_formats::FormatNumber;

namespace {

constexpr double kMaxExtentM = 10.0;  // larger meshes are probably in millimetres

std::string ReadWholeFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) Fail(path, "is a directory, not a mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path, "cannot open file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) Fail(path, "cannot read file");
  std::string data(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  if (size > 0 && !in.read(&data[0], size)) Fail(path, "cannot read file");
  return data;
}

void CheckLoaded(const std::string& path, const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) Fail(path, "no triangles");
  const double extent = (mesh.BoundsMax() - mesh.BoundsMin()).maxCoeff();
  if (extent > kMaxExtentM) {
    Fail(path, "extent " + FormatNumber(extent) + " m is over " + FormatNumber(kMaxExtentM) +
                   " m: is the mesh in millimetres?");
  }
}

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Zero area to rounding: the cross product is tiny against the longest edge.
bool IsDegenerate(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  Eigen::Vector3d* cross) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  *cross = ab.cross(ac);
  const double longest2 = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  return longest2 == 0.0 || cross->norm() <= 1e-12 * longest2;
}

// The reference point for volume sums (the bounds centre keeps the sums
// accurate for meshes far from their origin; a closed mesh's result does not
// depend on it).
Eigen::Vector3d ReferencePoint(const TriangleMesh& mesh) {
  return 0.5 * (mesh.BoundsMin() + mesh.BoundsMax());
}

void CheckIndices(const TriangleMesh& mesh, const char* caller) {
  const auto n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= n) {
        throw std::invalid_argument(std::string(caller) + ": triangle " + std::to_string(t) +
                                    " refers to vertex " + std::to_string(tri[k]) +
                                    " but the mesh has " + std::to_string(n) + " vertices");
      }
    }
  }
}

// Counts how the undirected edges of a mesh are used, in linear time: the
// half-edges are bucketed by their lower vertex (a counting sort), and each
// bucket is grouped by its higher vertex through a per-vertex marker.
struct EdgeCounts {
  std::size_t boundary = 0;
  std::size_t nonmanifold = 0;
  std::size_t inconsistent = 0;
};

EdgeCounts CountEdges(const TriangleMesh& mesh, const std::vector<char>& skip) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::uint32_t> start(n + 1, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (skip[t]) continue;
    const Eigen::Vector3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      ++start[static_cast<std::size_t>(std::min(tri[k], tri[(k + 1) % 3])) + 1];
    }
  }
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  // Each half-edge as (higher vertex << 1) | (1 if it runs from lower to higher).
  std::vector<std::uint32_t> half_edges(start[n]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (skip[t]) continue;
    const Eigen::Vector3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int from = tri[k];
      const int to = tri[(k + 1) % 3];
      const auto lo = static_cast<std::size_t>(std::min(from, to));
      const auto hi = static_cast<std::uint32_t>(std::max(from, to));
      half_edges[fill[lo]++] = (hi << 1) | (from < to ? 1u : 0u);
    }
  }
  EdgeCounts counts;
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> marker(n, kNone);     // the bucket that last saw each vertex
  std::vector<std::uint32_t> group(n, 0);          // its edge's index in `uses`
  std::vector<std::array<std::uint32_t, 2>> uses;  // (count, forward) per edge of a bucket
  for (std::size_t lo = 0; lo < n; ++lo) {
    uses.clear();
    for (std::uint32_t e = start[lo]; e < start[lo + 1]; ++e) {
      const std::uint32_t hi = half_edges[e] >> 1;
      if (marker[hi] != lo) {
        marker[hi] = static_cast<std::uint32_t>(lo);
        group[hi] = static_cast<std::uint32_t>(uses.size());
        uses.push_back({0, 0});
      }
      auto& use = uses[group[hi]];
      ++use[0];
      use[1] += half_edges[e] & 1u;
    }
    for (const auto& use : uses) {
      if (use[0] == 1) {
        ++counts.boundary;
      } else if (use[0] > 2) {
        ++counts.nonmanifold;
      } else if (use[1] != 1) {
        ++counts.inconsistent;
      }
    }
  }
  return counts;
}

}  // namespace

// ---------------------------------------------------------------------------

Eigen::Vector3d TriangleMesh::BoundsMin() const {
  if (vertices.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d lo = vertices.front();
  for (const Eigen::Vector3d& v : vertices) lo = lo.cwiseMin(v);
  return lo;
}

Eigen::Vector3d TriangleMesh::BoundsMax() const {
  if (vertices.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = vertices.front();
  for (const Eigen::Vector3d& v : vertices) hi = hi.cwiseMax(v);
  return hi;
}

Eigen::Vector3d TriangleMesh::TriangleNormal(std::size_t i) const {
  if (i >= triangles.size()) {
    throw std::out_of_range("TriangleNormal: triangle " + std::to_string(i) + " of " +
                            std::to_string(triangles.size()));
  }
  const Eigen::Vector3i& t = triangles[i];
  Eigen::Vector3d cross;
  if (IsDegenerate(vertices.at(static_cast<std::size_t>(t[0])),
                   vertices.at(static_cast<std::size_t>(t[1])),
                   vertices.at(static_cast<std::size_t>(t[2])), &cross)) {
    return Eigen::Vector3d::Zero();
  }
  return cross.normalized();
}

std::string MeshCheck::Describe() const {
  std::vector<std::string> parts;
  const auto add = [&parts](std::size_t n, const char* one, const char* many) {
    if (n > 0) parts.push_back(std::to_string(n) + " " + (n == 1 ? one : many));
  };
  if (IsClosed()) parts.push_back("closed, volume " + FormatNumber(signed_volume_m3) + " m^3");
  add(boundary_edges, "boundary edge", "boundary edges");
  add(nonmanifold_edges, "non-manifold edge", "non-manifold edges");
  add(inconsistent_edges, "inconsistently oriented edge", "inconsistently oriented edges");
  if (boundary_edges == 0 && nonmanifold_edges == 0 && inconsistent_edges == 0 &&
      signed_volume_m3 <= 0.0) {
    parts.push_back("triangles face inwards (signed volume " + FormatNumber(signed_volume_m3) +
                    " m^3)");
  }
  add(degenerate_triangles, "degenerate triangle", "degenerate triangles");
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

MeshCheck CheckMesh(const TriangleMesh& mesh) {
  CheckIndices(mesh, "CheckMesh");
  MeshCheck check;
  const Eigen::Vector3d r = ReferencePoint(mesh);
  std::vector<char> folded(mesh.triangles.size(), 0);  // repeated vertex: no edges to count
  double volume6 = 0.0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      folded[i] = 1;
      ++check.degenerate_triangles;
      continue;
    }
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    Eigen::Vector3d cross;
    if (IsDegenerate(a, b, c, &cross)) ++check.degenerate_triangles;
    volume6 += (a - r).dot((b - r).cross(c - r));
  }
  const EdgeCounts edges = CountEdges(mesh, folded);
  check.boundary_edges = edges.boundary;
  check.nonmanifold_edges = edges.nonmanifold;
  check.inconsistent_edges = edges.inconsistent;
  check.signed_volume_m3 = volume6 / 6.0;
  return check;
}

TriangleMesh LoadMeshAnyScale(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext != ".ply" && ext != ".obj" && ext != ".stl" && ext != ".cao") {
    Fail(path, "unknown mesh format '" + ext + "' (expected .ply, .obj, .stl or .cao)");
  }
  const std::string data = ReadWholeFile(path);
  TriangleMesh mesh;
  if (ext == ".ply") {
    mesh = mesh_formats::LoadPly(path, data);
  } else if (ext == ".obj") {
    mesh = mesh_formats::LoadObj(path, data);
  } else if (ext == ".cao") {
    mesh = mesh_formats::LoadCao(path, data);
  } else {
    mesh = mesh_formats::LoadStl(path, data);
  }
  if (mesh.triangles.empty()) Fail(path, "no triangles");
  return mesh;
}

TriangleMesh LoadMesh(const std::string& path) {
  TriangleMesh mesh = LoadMeshAnyScale(path);
  CheckLoaded(path, mesh);
  return mesh;
}

TriangleMesh LoadClosedMesh(const std::string& path) {
  TriangleMesh mesh = LoadMesh(path);
  const MeshCheck check = CheckMesh(mesh);
  if (!check.IsClosed()) {
    Fail(path, "mesh is not a closed solid: " + check.Describe() +
                   " (grasp planning and mass properties need a closed, consistently "
                   "oriented mesh with outward-facing triangles)");
  }
  return mesh;
}

void SaveMeshPly(const TriangleMesh& mesh, const std::string& path) {
  mesh_formats::SavePly(mesh, path);
}

MassProperties ComputeMassProperties(const TriangleMesh& mesh) {
  CheckIndices(mesh, "ComputeMassProperties");
  // Sum of the signed tetrahedra (r, a, b, c); r is the reference point.
  const Eigen::Vector3d r = ReferencePoint(mesh);
  double volume6 = 0.0;
  Eigen::Vector3d moment24 = Eigen::Vector3d::Zero();  // 24 * integral of (p - r) dV
  // 120 * integral of (p - r)(p - r)^T dV: per tetrahedron (r, a, b, c),
  // det * (a a^T + b b^T + c c^T + s s^T) with s = a + b + c.
  Eigen::Matrix3d second120 = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[static_cast<std::size_t>(t[0])] - r;
    const Eigen::Vector3d b = mesh.vertices[static_cast<std::size_t>(t[1])] - r;
    const Eigen::Vector3d c = mesh.vertices[static_cast<std::size_t>(t[2])] - r;
    const double v6 = a.dot(b.cross(c));
    volume6 += v6;
    const Eigen::Vector3d s = a + b + c;
    moment24 += v6 * s;
    second120 +=
        v6 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  MassProperties properties;
  properties.volume_m3 = volume6 / 6.0;
  // A mesh without volume has no centre of mass; report the reference point.
  const Eigen::Vector3d offset =
      volume6 != 0.0 ? Eigen::Vector3d(moment24 / (4.0 * volume6)) : Eigen::Vector3d::Zero();
  properties.center_of_mass = r + offset;
  // Second moment about the centre of mass (parallel axis), then the inertia.
  const Eigen::Matrix3d second =
      second120 / 120.0 - properties.volume_m3 * offset * offset.transpose();
  properties.inertia_unit_density = second.trace() * Eigen::Matrix3d::Identity() - second;
  return properties;
}

std::vector<double> IntersectRay(const TriangleMesh& mesh, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& direction) {
  // Moller-Trumbore per triangle, keeping whether the ray enters (det > 0:
  // against the outward normal of a counter-clockwise triangle) or leaves.
  std::vector<std::pair<double, bool>> found;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d e1 = mesh.vertices[t[1]] - a, e2 = mesh.vertices[t[2]] - a;
    const Eigen::Vector3d p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double dist = e2.dot(q) / det;
    if (dist >= 0.0) found.emplace_back(dist, det > 0.0);
  }
  std::sort(found.begin(), found.end());
  // A ray through an edge or vertex shared by several triangles meets each of
  // them (the bounds above are inclusive): hits at one distance crossing the
  // same way are one crossing. One entering and one leaving hit at one distance
  // (a ray touching a silhouette edge) both stay, so parity still tells inside.
  constexpr double kSame = 1e-9;  // in units of |direction|
  std::vector<double> hits;
  for (std::size_t i = 0; i < found.size();) {
    std::size_t end = i;
    bool entering = false, leaving = false;
    for (; end < found.size() && found[end].first - found[i].first <= kSame; ++end) {
      (found[end].second ? entering : leaving) = true;
    }
    if (entering) hits.push_back(found[i].first);
    if (leaving) hits.push_back(found[i].first);
    i = end;
  }
  return hits;
}

}  // namespace aerograsp
