// `aerograsp object import MESH --name NAME`: a user's mesh (PLY, OBJ, STL or
// ViSP .cao) checked, repaired where that is honest, measured (mass
// properties, rotational symmetry) and stored as an object folder every
// command finds by name (docs/objects.md); `aerograsp object show NAME`.
#pragma once

#include <ostream>
#include <string>

#include "core/symmetry.h"

namespace CLI {
class App;
}

namespace aerograsp {

/// The import's tuned values (data/config/object_import.yaml documents each).
struct ObjectImportConfig {
  double min_extent_m = 0.01;
  double max_extent_m = 1.5;
  double min_thickness_m = 0.001;
  double merge_distance_ratio = 1e-6;
  SymmetryOptions symmetry;

  /// `prefix` is the key path of this tree in `source`, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
  /// @throws ConfigError for an unreadable file, an unknown key or a bad value.
  static ObjectImportConfig Load(const std::string& path);
};

struct ObjectImportOptions {
  std::string mesh_path;
  std::string name;
  std::string units = "m";  ///< the file's length unit: m, cm or mm
  double mass_kg = 0.0;     ///< 0: from the volume at ObjectModel::kDefaultDensity
  std::string objects_dir;  ///< empty: DefaultObjectImportDir()
  std::string config_path;  ///< empty: data/config/object_import.yaml
  bool overwrite = false;   ///< replace an object of that name in objects_dir
};

/// `object show`'s options.
struct ObjectShowOptions {
  std::string object;        ///< an object name or path
  bool folder_only = false;  ///< print the object's folder alone
};

/// Imports the mesh and prints what was checked, repaired and found.
/// @returns the folder written (objects_dir/NAME).
/// @throws MeshError / ConfigError naming the file and what is wrong; nothing
/// is left in objects_dir then.
std::string RunObjectImport(const ObjectImportOptions& options, std::ostream& out);

/// `aerograsp object show NAME`: where the object is and what it is (mesh,
/// mass, symmetry, detector). `folder_only`: print the object's folder alone
/// (for scripts).
/// @throws ConfigError / MeshError as ObjectModel::Load; ConfigError when
/// `folder_only` and the object is a bare mesh file, not an object folder.
void RunObjectShow(const std::string& what, bool folder_only, std::ostream& out);

/// Adds `object import`'s options to `cmd` (a CLI11 subcommand).
void AddObjectImportOptions(CLI::App* cmd, ObjectImportOptions* options);

/// Adds `object show`'s options to `cmd` (a CLI11 subcommand).
void AddObjectShowOptions(CLI::App* cmd, ObjectShowOptions* options);

}  // namespace aerograsp
