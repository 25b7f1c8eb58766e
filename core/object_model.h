// A known object: its closed mesh in frame o, its mass properties and its
// rotational symmetries, from an object folder (NAME/object.yaml: the shipped
// ones in data/objects, see tools/make_objects.py, and the ones `aerograsp
// object import` writes) or from a user's mesh file.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/symmetry.h"

namespace aerograsp {

struct ObjectModel {
  std::string name;
  std::string source;     ///< the object.yaml or mesh file it was read from (absolute)
  std::string reference;  ///< what Load takes to find it again: its name, or `source`
  TriangleMesh mesh_o;    ///< closed, in frame o (metres)
  double mass_kg = 0.0;
  bool mass_estimated = false;  ///< true when the mass came from the volume at kDefaultDensity
  Eigen::Vector3d center_of_mass_o = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_kg_m2 = Eigen::Matrix3d::Zero();  ///< about the centre of mass, axes of o
  Eigen::Vector3d dimensions_m = Eigen::Vector3d::Zero();   ///< bounding box extents in o
  ObjectSymmetry symmetry;  ///< from object.yaml's `symmetry`, else found on the mesh

  /// Density assumed for a bare mesh (kg/m^3): a hollow plastic part.
  static constexpr double kDefaultDensity = 300.0;

  /// `what` is an object name (a folder NAME/object.yaml in one of
  /// ObjectSearchDirs(), first match), a folder holding object.yaml, an
  /// object.yaml, or a mesh file (PLY, OBJ, STL, .cao).
  /// @throws ConfigError / MeshError naming the file: no such object (listing
  /// the known names and the folders searched), a malformed yaml, a mesh that
  /// is missing or not closed.
  static ObjectModel Load(const std::string& what);
};

/// The folders where objects are found by name, in the order searched: the
/// folders in $AEROGRASP_OBJECTS_DIR (':'-separated), the user's folder
/// ($XDG_DATA_HOME, else ~/.local/share, /aerograsp/objects), then the shipped
/// data/objects.
std::vector<std::string> ObjectSearchDirs();

/// Where `object import` writes by default: the first folder of
/// $AEROGRASP_OBJECTS_DIR when set, else data/objects beside the shipped ones.
std::string DefaultObjectImportDir();

/// The names of the objects in `dir` (folders with an object.yaml), sorted.
std::vector<std::string> ObjectNamesIn(const std::string& dir);

/// The names of the shipped objects (folders of data/objects with an object.yaml), sorted.
std::vector<std::string> ShippedObjectNames();

/// The object's detector (a box detector's ONNX model): detector.onnx beside
/// the file it was read from, where scripts/train_detectors.sh writes it in
/// its object folder; empty when there is none.
std::string ObjectDetectorPath(const ObjectModel& object);

/// The point of an object that the commands placing it themselves (plan,
/// record, dataset, mission) put where they are asked: the centre of its
/// bounding box in o, whatever o's origin (the origin itself for the shipped
/// objects).
Eigen::Vector3d PlacementCentre(const TriangleMesh& mesh_o);

/// xMo of the object whose placement centre is at xMcentre (axes of o).
Eigen::Isometry3d PlaceByCentre(const Eigen::Isometry3d& xMcentre, const TriangleMesh& mesh_o);

}  // namespace aerograsp
