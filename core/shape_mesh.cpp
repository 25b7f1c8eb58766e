#include "core/shape_mesh.h"

#include <Eigen/Geometry>
#include <cmath>

namespace aerograsp {

TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  const Eigen::Vector3d h = 0.5 * size_m;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                               (i & 4) ? h.z() : -h.z());
  }
  // Two counter-clockwise (seen from outside) triangles per face.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

TriangleMesh MakeCylinderMesh(double radius_m, double length_m, int segments) {
  TriangleMesh mesh;
  const double h = 0.5 * length_m;
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * M_PI * i / segments;
    mesh.vertices.emplace_back(radius_m * std::cos(a), radius_m * std::sin(a), -h);
    mesh.vertices.emplace_back(radius_m * std::cos(a), radius_m * std::sin(a), h);
  }
  const int bottom = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0, 0, -h);
  mesh.vertices.emplace_back(0, 0, h);
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    mesh.triangles.emplace_back(2 * i, 2 * j, 2 * j + 1);
    mesh.triangles.emplace_back(2 * i, 2 * j + 1, 2 * i + 1);
    mesh.triangles.emplace_back(bottom, 2 * j, 2 * i);
    mesh.triangles.emplace_back(bottom + 1, 2 * i + 1, 2 * j + 1);
  }
  return mesh;
}

TriangleMesh MakeSphereMesh(double radius_m, int rings, int segments) {
  TriangleMesh mesh;
  mesh.vertices.emplace_back(0, 0, -radius_m);
  for (int r = 1; r < rings; ++r) {
    const double polar = M_PI * r / rings;  // from the south pole
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * M_PI * s / segments;
      mesh.vertices.emplace_back(radius_m * std::sin(polar) * std::cos(a),
                                 radius_m * std::sin(polar) * std::sin(a),
                                 -radius_m * std::cos(polar));
    }
  }
  const int north = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0, 0, radius_m);
  auto ring_vertex = [segments](int r, int s) { return 1 + (r - 1) * segments + s % segments; };
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.emplace_back(0, ring_vertex(1, s + 1), ring_vertex(1, s));
    mesh.triangles.emplace_back(north, ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1));
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.triangles.emplace_back(ring_vertex(r, s), ring_vertex(r, s + 1),
                                  ring_vertex(r + 1, s + 1));
      mesh.triangles.emplace_back(ring_vertex(r, s), ring_vertex(r + 1, s + 1),
                                  ring_vertex(r + 1, s));
    }
  }
  return mesh;
}

TriangleMesh MeshFromShape(const CollisionShape& shape) {
  TriangleMesh local;
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      local = MakeBoxMesh(shape.size);
      break;
    case CollisionShape::Type::kCylinder:
      local = MakeCylinderMesh(shape.size.x(), shape.size.y());
      break;
    case CollisionShape::Type::kSphere:
      local = MakeSphereMesh(shape.size.x());
      break;
    case CollisionShape::Type::kMesh:
      local = LoadMesh(shape.mesh_path);
      for (auto& v : local.vertices) v = v.cwiseProduct(shape.size);
      break;
  }
  TriangleMesh mesh;
  AppendMesh(local, shape.segMs, &mesh);
  return mesh;
}

void AppendMesh(const TriangleMesh& part, const Eigen::Isometry3d& aMpart, TriangleMesh* mesh) {
  const bool keep_colors =
      !part.colors.empty() && (mesh->vertices.empty() || !mesh->colors.empty());
  if (!keep_colors) mesh->colors.clear();
  const int offset = static_cast<int>(mesh->vertices.size());
  for (const auto& v : part.vertices) mesh->vertices.push_back(aMpart * v);
  for (const auto& t : part.triangles) mesh->triangles.push_back(t.array() + offset);
  if (keep_colors) mesh->colors.insert(mesh->colors.end(), part.colors.begin(), part.colors.end());
}

}  // namespace aerograsp
