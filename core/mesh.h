// Triangle meshes of objects and robot parts, in metres, in the frame they are
// written in (for an object, the object frame o).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace aerograsp {

/// Thrown for a mesh file that cannot be used; the message starts with the path.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An indexed triangle mesh. Triangles are counter-clockwise seen from outside
/// (their normal (b-a)x(c-a) points out of a closed mesh).
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;            ///< metres
  std::vector<Eigen::Vector3i> triangles;           ///< indices into vertices
  std::vector<std::array<std::uint8_t, 3>> colors;  ///< RGB per vertex; empty if none

  /// Axis-aligned bounds; both zero for an empty mesh.
  Eigen::Vector3d BoundsMin() const;
  Eigen::Vector3d BoundsMax() const;
  /// Unit outward normal of triangle i (zero for a degenerate triangle).
  Eigen::Vector3d TriangleNormal(std::size_t i) const;
};

/// What CheckMesh found: the defects that matter for ray casting, mass
/// properties and collision checking.
struct MeshCheck {
  std::size_t degenerate_triangles = 0;  ///< zero area
  std::size_t boundary_edges = 0;        ///< edges used by one triangle only (holes)
  std::size_t nonmanifold_edges = 0;     ///< edges used by more than two triangles
  std::size_t inconsistent_edges = 0;    ///< edges whose two triangles disagree in orientation
  double signed_volume_m3 = 0.0;         ///< negative when the triangles face inwards

  /// Closed, 2-manifold, consistently oriented with outward normals.
  bool IsClosed() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && inconsistent_edges == 0 &&
           signed_volume_m3 > 0.0;
  }
  /// One line a user can read, e.g. "12 boundary edges, 3 inconsistent edges".
  std::string Describe() const;
};

/// Loads a PLY (ASCII or binary little/big endian), OBJ, STL (ASCII or
/// binary) or ViSP .cao mesh, chosen by the file's extension (case-insensitive). Vertex
/// colours are read from PLY (red/green/blue uchar) and from OBJ `v x y z r g b`
/// lines (floats 0..1).
/// @throws MeshError naming the path when the file is missing, unreadable, of
/// an unknown format, truncated, has no triangles, a non-finite coordinate, an
/// index out of range, or an extent over 10 m (probably millimetres).
TriangleMesh LoadMesh(const std::string& path);

/// LoadMesh without the extent check, for a caller that applies the file's
/// units itself (object import).
TriangleMesh LoadMeshAnyScale(const std::string& path);

/// Counts the defects of a mesh (see MeshCheck). Linear time in the triangles.
MeshCheck CheckMesh(const TriangleMesh& mesh);

/// LoadMesh, then throws MeshError naming the path and CheckMesh's findings when
/// the mesh is not closed (grasp planning and mass properties need a solid).
TriangleMesh LoadClosedMesh(const std::string& path);

/// Writes a binary little-endian PLY with vertex colours when the mesh has them.
/// @throws MeshError when the file cannot be written.
void SaveMeshPly(const TriangleMesh& mesh, const std::string& path);

/// The distances t >= 0 (sorted, in units of |direction|) at which the ray
/// origin + t * direction crosses a triangle of the mesh (both faces count).
/// A crossing through an edge or vertex shared by triangles counts once (hits
/// within 1e-9 of each other crossing the same way, in or out, are merged).
/// Brute force over the triangles: for single rays, not images.
std::vector<double> IntersectRay(const TriangleMesh& mesh, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& direction);

/// Volume (m^3), centre of mass (in the mesh frame, uniform density) and the
/// inertia at unit density of a closed mesh, by the divergence theorem.
struct MassProperties {
  double volume_m3 = 0.0;
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();
  /// Inertia tensor about the centre of mass, axes of the mesh frame, at a
  /// density of 1 kg/m^3 (kg m^2 per kg/m^3, i.e. m^5): times the density.
  Eigen::Matrix3d inertia_unit_density = Eigen::Matrix3d::Zero();
};
MassProperties ComputeMassProperties(const TriangleMesh& mesh);

}  // namespace aerograsp
