// Small closed meshes for tests, built in code so each test shows its geometry.
#pragma once

#include <Eigen/Geometry>

#include "core/mesh.h"
#include "core/shape_mesh.h"

namespace aerograsp {
namespace test {

/// A closed axis-aligned box mesh of full extents `size` centred at `center`.
inline TriangleMesh BoxMesh(const Eigen::Vector3d& size,
                            const Eigen::Vector3d& center = Eigen::Vector3d::Zero()) {
  TriangleMesh m;
  AppendMesh(MakeBoxMesh(size), Eigen::Isometry3d(Eigen::Translation3d(center)), &m);
  return m;
}

/// The union of two meshes' triangles (disjoint solids stay a closed mesh).
inline TriangleMesh MergeMeshes(TriangleMesh a, const TriangleMesh& b) {
  AppendMesh(b, Eigen::Isometry3d::Identity(), &a);
  return a;
}

}  // namespace test
}  // namespace aerograsp
