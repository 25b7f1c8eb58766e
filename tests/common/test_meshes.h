// Small closed meshes for tests, built in code so each test shows its geometry.
#pragma once

#include <Eigen/Geometry>
#include <utility>

#include "core/mesh.h"

namespace aerograsp {
namespace test {

/// A closed axis-aligned box mesh of full extents `size` centred at `center`,
/// triangles facing outwards.
inline TriangleMesh BoxMesh(const Eigen::Vector3d& size,
                            const Eigen::Vector3d& center = Eigen::Vector3d::Zero()) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back(center.x() + (i & 1 ? 0.5 : -0.5) * size.x(),
                            center.y() + (i & 2 ? 0.5 : -0.5) * size.y(),
                            center.z() + (i & 4 ? 0.5 : -0.5) * size.z());
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int b1 = 1 << ((axis + 1) % 3), b2 = 1 << ((axis + 2) % 3);
      const int base = side ? 1 << axis : 0;
      const int quad[4] = {base, base | b1, base | b1 | b2, base | b2};
      for (Eigen::Vector3i t : {Eigen::Vector3i(quad[0], quad[1], quad[2]),
                                Eigen::Vector3i(quad[0], quad[2], quad[3])}) {
        const Eigen::Vector3d& a = m.vertices[t[0]];
        const Eigen::Vector3d n = (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a);
        if (n.dot(a + m.vertices[t[1]] + m.vertices[t[2]] - 3.0 * center) < 0.0) {
          std::swap(t[1], t[2]);
        }
        m.triangles.push_back(t);
      }
    }
  }
  return m;
}

/// The union of two meshes' triangles (disjoint solids stay a closed mesh).
inline TriangleMesh MergeMeshes(TriangleMesh a, const TriangleMesh& b) {
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Eigen::Vector3i& t : b.triangles) a.triangles.push_back(t + Eigen::Vector3i::Constant(offset));
  return a;
}

}  // namespace test
}  // namespace aerograsp
