#include "core/mesh_repair.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <set>
#include <sstream>
#include <unordered_map>

namespace aerograsp {
namespace {

std::string Point(const Eigen::Vector3d& p, const std::string& unit) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ") " << unit;
  return out.str();
}

std::uint64_t EdgeKey(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

/// Merges vertices closer than `distance` (the first one of each group stays);
/// returns the new index of every old vertex.
std::vector<int> MergeVertices(TriangleMesh* mesh, double distance, std::size_t* merged) {
  const std::size_t n = mesh->vertices.size();
  std::vector<int> remap(n);
  std::vector<Eigen::Vector3d> kept;
  std::vector<std::array<std::uint8_t, 3>> kept_colors;
  const bool colored = mesh->colors.size() == n && n > 0;
  const double cell = distance > 0.0 ? distance : 1.0;
  const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(x * 73856093) ^ static_cast<std::uint64_t>(y * 19349663) ^
           static_cast<std::uint64_t>(z * 83492791);
  };
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  grid.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    const Eigen::Vector3d& p = mesh->vertices[v];
    const std::int64_t cx = static_cast<std::int64_t>(std::floor(p.x() / cell));
    const std::int64_t cy = static_cast<std::int64_t>(std::floor(p.y() / cell));
    const std::int64_t cz = static_cast<std::int64_t>(std::floor(p.z() / cell));
    int found = -1;
    for (std::int64_t dz = -1; dz <= 1 && found < 0; ++dz) {
      for (std::int64_t dy = -1; dy <= 1 && found < 0; ++dy) {
        for (std::int64_t dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (const int k : it->second) {
            if ((kept[static_cast<std::size_t>(k)] - p).norm() <= distance) {
              found = k;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(p);
      if (colored) kept_colors.push_back(mesh->colors[v]);
      grid[key(cx, cy, cz)].push_back(found);
    } else {
      ++*merged;
    }
    remap[v] = found;
  }
  mesh->vertices = std::move(kept);
  mesh->colors = std::move(kept_colors);
  return remap;
}

struct EdgeUse {
  int triangle;
  bool forward;  ///< the triangle runs lower -> higher vertex index along it
};

}  // namespace

std::vector<std::string> MeshRepairReport::Lines() const {
  std::vector<std::string> lines;
  const auto add = [&lines](std::size_t n, const std::string& what) {
    if (n > 0) lines.push_back(what + ": " + std::to_string(n));
  };
  add(merged_vertices, "duplicate vertices merged");
  add(dropped_collapsed, "collapsed triangles dropped (a repeated corner once duplicates merged)");
  add(dropped_duplicates, "repeated triangles dropped");
  add(flipped_triangles, "triangles turned to face out, consistently with their neighbours");
  add(dropped_unused_vertices, "unused vertices dropped");
  return lines;
}

MeshRepairReport RepairMesh(TriangleMesh* mesh, double merge_distance, const std::string& source,
                            const std::string& unit_name) {
  MeshRepairReport report;
  const auto fail = [&source](const std::string& what) { throw MeshError(source + ": " + what); };
  const std::vector<int> remap = MergeVertices(mesh, merge_distance, &report.merged_vertices);

  // Triangles on the merged vertices, without collapsed and repeated ones.
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Eigen::Vector3i> original;  // as read, to count the flips at the end
  std::set<std::array<int, 3>> seen;
  for (const Eigen::Vector3i& t : mesh->triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || static_cast<std::size_t>(t[k]) >= remap.size()) {
        fail("a triangle refers to vertex " + std::to_string(t[k]) + " of " +
             std::to_string(remap.size()));
      }
    }
    const Eigen::Vector3i m(remap[static_cast<std::size_t>(t[0])],
                            remap[static_cast<std::size_t>(t[1])],
                            remap[static_cast<std::size_t>(t[2])]);
    if (m[0] == m[1] || m[1] == m[2] || m[2] == m[0]) {
      ++report.dropped_collapsed;
      continue;
    }
    std::array<int, 3> sorted = {m[0], m[1], m[2]};
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) {
      ++report.dropped_duplicates;
      continue;
    }
    triangles.push_back(m);
  }
  if (triangles.empty()) fail("no triangles left once duplicate vertices are merged");
  original = triangles;

  // Edges: which triangles use each, and in which direction.
  std::unordered_map<std::uint64_t, std::vector<EdgeUse>> edges;
  edges.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      edges[EdgeKey(a, b)].push_back({static_cast<int>(t), a < b});
    }
  }
  std::vector<std::pair<int, int>> open, shared;
  for (const auto& [key, uses] : edges) {
    const auto edge =
        std::make_pair(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
    if (uses.size() == 1) open.push_back(edge);
    if (uses.size() > 2) shared.push_back(edge);
  }
  std::sort(open.begin(), open.end());
  std::sort(shared.begin(), shared.end());
  const auto where = [&](const std::vector<std::pair<int, int>>& list) {
    std::string text;
    for (std::size_t i = 0; i < std::min<std::size_t>(list.size(), 3); ++i) {
      const Eigen::Vector3d& a = mesh->vertices[static_cast<std::size_t>(list[i].first)];
      const Eigen::Vector3d& b = mesh->vertices[static_cast<std::size_t>(list[i].second)];
      text += (i ? "; " : "") + Point(a, unit_name) + " - " + Point(b, unit_name);
    }
    return text + (list.size() > 3 ? "; ..." : "");
  };
  if (!open.empty()) {
    // Holes: the open edges grouped by shared vertices.
    std::unordered_map<int, int> parent;
    const std::function<int(int)> find = [&](int v) {
      auto it = parent.find(v);
      if (it == parent.end()) return parent[v] = v;
      return it->second == v ? v : (it->second = find(it->second));
    };
    for (const auto& [a, b] : open) {
      const int ra = find(a), rb = find(b);
      parent[ra] = rb;
    }
    std::unordered_map<int, std::pair<Eigen::Vector3d, int>> holes;  // root -> (sum, count)
    for (const auto& [a, b] : open) {
      auto& hole = holes.try_emplace(find(a), Eigen::Vector3d::Zero(), 0).first->second;
      hole.first += 0.5 * (mesh->vertices[static_cast<std::size_t>(a)] +
                           mesh->vertices[static_cast<std::size_t>(b)]);
      ++hole.second;
    }
    std::vector<std::pair<int, Eigen::Vector3d>> list;
    for (const auto& [root, hole] : holes) list.emplace_back(hole.second, hole.first / hole.second);
    std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) {
      return x.first != y.first ? x.first > y.first : x.second.x() < y.second.x();
    });
    std::string around;
    for (std::size_t i = 0; i < std::min<std::size_t>(list.size(), 3); ++i) {
      around += (i ? "; " : "") + std::to_string(list[i].first) + " edges around " +
                Point(list[i].second, unit_name);
    }
    fail("the mesh is open: " + std::to_string(open.size()) + " open edges (used by one triangle " +
         "only) in " + std::to_string(list.size()) + (list.size() == 1 ? " hole" : " holes") +
         " (" + around + (list.size() > 3 ? "; ..." : "") + "), e.g. edges " + where(open) +
         ". A hole cannot be filled without guessing the shape: close it in the CAD tool "
         "(export a solid, or fill the holes) and import again");
  }
  if (!shared.empty()) {
    fail(std::to_string(shared.size()) + (shared.size() == 1 ? " edge is" : " edges are") +
         " shared by more than two triangles (surfaces touching along an edge, or "
         "faces inside the solid), e.g. " +
         where(shared) + ": export one closed solid");
  }

  // Orientation: each shell walked from one triangle, neighbours turned to
  // run each shared edge the other way.
  const std::size_t nt = triangles.size();
  std::vector<int> shell(nt, -1);
  std::vector<char> flip(nt, 0);
  std::vector<std::vector<int>> shells;
  for (std::size_t start = 0; start < nt; ++start) {
    if (shell[start] >= 0) continue;
    const int id = static_cast<int>(shells.size());
    shells.emplace_back();
    std::vector<int> stack = {static_cast<int>(start)};
    shell[start] = id;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      shells.back().push_back(t);
      const Eigen::Vector3i& tri = triangles[static_cast<std::size_t>(t)];
      for (int k = 0; k < 3; ++k) {
        const int a = tri[k], b = tri[(k + 1) % 3];
        // Direction of this edge in t as it will be once t is flipped or not.
        const bool forward_t = (a < b) != static_cast<bool>(flip[static_cast<std::size_t>(t)]);
        for (const EdgeUse& use : edges[EdgeKey(a, b)]) {
          if (use.triangle == t) continue;
          const auto u = static_cast<std::size_t>(use.triangle);
          // Consistent: u runs the edge the other way.
          const bool want_flip = use.forward == forward_t;
          if (shell[u] < 0) {
            shell[u] = id;
            flip[u] = want_flip;
            stack.push_back(use.triangle);
          } else if (static_cast<bool>(flip[u]) != want_flip) {
            fail("the surface cannot be oriented (it is one-sided, like a Moebius strip) near " +
                 Point(mesh->vertices[static_cast<std::size_t>(a)], unit_name));
          }
        }
      }
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    if (flip[t]) std::swap(triangles[t][1], triangles[t][2]);
  }
  report.shells = shells.size();

  // Each shell faces out (positive volume) unless it lies inside an odd
  // number of others (a cavity faces in).
  std::vector<TriangleMesh> parts(shells.size());
  std::vector<double> volume(shells.size(), 0.0);
  for (std::size_t s = 0; s < shells.size(); ++s) {
    parts[s].vertices = mesh->vertices;
    for (const int t : shells[s])
      parts[s].triangles.push_back(triangles[static_cast<std::size_t>(t)]);
    volume[s] = ComputeMassProperties(parts[s]).volume_m3;
    const Eigen::Vector3d lo = parts[s].BoundsMin(), hi = parts[s].BoundsMax();
    if (!(std::abs(volume[s]) > 1e-9 * (hi - lo).prod()) || (hi - lo).minCoeff() <= 0.0) {
      fail("a closed surface around " + Point(0.5 * (lo + hi), unit_name) +
           " encloses no volume (it is flat): export the solid, not a sheet");
    }
  }
  constexpr std::size_t kMaxNestingTests = 200;  // shells tested for lying inside another
  const Eigen::Vector3d ray = Eigen::Vector3d(0.5773, 0.5774, 0.5776).normalized();
  for (std::size_t s = 0; s < shells.size(); ++s) {
    int depth = 0;
    if (shells.size() <= kMaxNestingTests) {
      const Eigen::Vector3d p = mesh->vertices[static_cast<std::size_t>(
          triangles[static_cast<std::size_t>(shells[s][0])][0])];
      for (std::size_t o = 0; o < shells.size(); ++o) {
        if (o != s && IntersectRay(parts[o], p, ray).size() % 2 == 1) ++depth;
      }
    }
    const bool want_positive = depth % 2 == 0;
    if ((volume[s] > 0.0) != want_positive) {
      for (const int t : shells[s]) {
        std::swap(triangles[static_cast<std::size_t>(t)][1],
                  triangles[static_cast<std::size_t>(t)][2]);
      }
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    // Same cyclic order as read, or turned.
    const Eigen::Vector3i& a = triangles[t];
    const Eigen::Vector3i& b = original[t];
    const bool same = (a == b) || (a == Eigen::Vector3i(b[1], b[2], b[0])) ||
                      (a == Eigen::Vector3i(b[2], b[0], b[1]));
    if (!same) ++report.flipped_triangles;
  }

  // Drop vertices no triangle uses.
  std::vector<int> used(mesh->vertices.size(), -1);
  TriangleMesh clean;
  const bool colored = mesh->colors.size() == mesh->vertices.size() && !mesh->colors.empty();
  for (Eigen::Vector3i& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      int& index = used[static_cast<std::size_t>(t[k])];
      if (index < 0) {
        index = static_cast<int>(clean.vertices.size());
        clean.vertices.push_back(mesh->vertices[static_cast<std::size_t>(t[k])]);
        if (colored) clean.colors.push_back(mesh->colors[static_cast<std::size_t>(t[k])]);
      }
      t[k] = index;
    }
  }
  report.dropped_unused_vertices = mesh->vertices.size() - clean.vertices.size();
  clean.triangles = std::move(triangles);
  *mesh = std::move(clean);
  return report;
}

}  // namespace aerograsp
