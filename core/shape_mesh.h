// Triangle meshes of the primitive shapes (boxes, cylinders, spheres) that
// URDF collision elements and the simulator's scene are made of.
#pragma once

#include <Eigen/Core>

#include "core/arm_model.h"
#include "core/mesh.h"

namespace aerograsp {

/// A closed box centred on the origin with full extents `size_m` (x, y, z).
TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size_m);

/// A closed cylinder along z, centred on the origin, with `segments` sides (>= 3).
TriangleMesh MakeCylinderMesh(double radius_m, double length_m, int segments = 24);

/// A closed UV sphere centred on the origin (rings >= 2, segments >= 3).
TriangleMesh MakeSphereMesh(double radius_m, int rings = 8, int segments = 16);

/// The mesh of a URDF collision shape in the frame that carries it (segMs
/// applied). A kMesh shape is loaded with LoadMesh and scaled.
/// @throws MeshError for a kMesh shape whose file cannot be loaded.
TriangleMesh MeshFromShape(const CollisionShape& shape);

/// Appends `part` to `mesh`, its vertices moved by `aMpart` (colours kept only
/// when both meshes have them or `mesh` is empty).
void AppendMesh(const TriangleMesh& part, const Eigen::Isometry3d& aMpart, TriangleMesh* mesh);

}  // namespace aerograsp
