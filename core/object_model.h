// A known object: its closed mesh in frame o and its mass properties, from a
// shipped model folder (data/objects/NAME/object.yaml, see
// tools/make_objects.py) or from a user's mesh file.
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/mesh.h"

namespace aerograsp {

struct ObjectModel {
  std::string name;
  std::string source;   ///< the object.yaml or mesh file it was read from
  TriangleMesh mesh_o;  ///< closed, in frame o (metres)
  double mass_kg = 0.0;
  bool mass_estimated = false;  ///< true when the mass came from the volume at kDefaultDensity
  Eigen::Vector3d center_of_mass_o = Eigen::Vector3d::Zero();
  Eigen::Vector3d dimensions_m = Eigen::Vector3d::Zero();  ///< bounding box extents in o

  /// Density assumed for a bare mesh (kg/m^3): a hollow plastic part.
  static constexpr double kDefaultDensity = 300.0;

  /// `what` is a shipped object name ("crawler"), a folder holding
  /// object.yaml, an object.yaml, or a mesh file (PLY, OBJ, STL).
  /// @throws ConfigError / MeshError naming the file: no such object (listing
  /// the shipped names), a malformed yaml, a mesh that is missing or not closed.
  static ObjectModel Load(const std::string& what);
};

/// The names of the shipped objects (folders of data/objects with an object.yaml), sorted.
std::vector<std::string> ShippedObjectNames();

}  // namespace aerograsp
