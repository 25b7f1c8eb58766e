#include "core/object_model.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/config.h"
#include "core/data_dir.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return text.empty() ? "none" : text;
}

/// object.yaml's `symmetry` map (written by `object import`, core/symmetry.h).
ObjectSymmetry ReadSymmetry(const ConfigNode& node) {
  node.RequireOnlyKeys({"center_m", "continuous_axis", "rotations_wxyz"});
  ObjectSymmetry symmetry;
  symmetry.center_o = node.GetVector3("center_m");
  if (node.Has("continuous_axis")) {
    const Eigen::Vector3d axis = node.GetVector3("continuous_axis");
    if (std::abs(axis.norm() - 1.0) > 1e-3) node.Fail("continuous_axis", "must be a unit vector");
    symmetry.continuous_axis_o = axis.normalized();
  }
  const std::vector<double> q = node.GetDoubles("rotations_wxyz");
  if (q.size() % 4 != 0 || q.empty()) {
    node.Fail("rotations_wxyz", "expected quaternions w x y z, 4 numbers each, the identity first");
  }
  for (std::size_t i = 0; i < q.size(); i += 4) {
    const Eigen::Quaterniond r(q[i], q[i + 1], q[i + 2], q[i + 3]);
    if (std::abs(r.norm() - 1.0) > 1e-3) {
      node.Fail("rotations_wxyz",
                "rotation " + std::to_string(i / 4) + " is not a unit quaternion");
    }
    symmetry.rotations.push_back(r.normalized().toRotationMatrix());
  }
  if (!symmetry.rotations.front().isIdentity(1e-6)) {
    node.Fail("rotations_wxyz", "the first rotation must be the identity (1 0 0 0)");
  }
  return symmetry;
}

}  // namespace

std::vector<std::string> ObjectSearchDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("AEROGRASP_OBJECTS_DIR"); env && *env) {
    const std::string list = env;
    std::size_t start = 0;
    while (start <= list.size()) {
      const std::size_t end = std::min(list.find(':', start), list.size());
      if (end > start) dirs.push_back(list.substr(start, end - start));
      start = end + 1;
    }
  }
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && *xdg) {
    dirs.push_back((fs::path(xdg) / "aerograsp" / "objects").string());
  } else if (const char* home = std::getenv("HOME"); home && *home) {
    dirs.push_back((fs::path(home) / ".local" / "share" / "aerograsp" / "objects").string());
  }
  dirs.push_back(DataPath("objects"));
  return dirs;
}

std::string DefaultObjectImportDir() {
  const std::vector<std::string> dirs = ObjectSearchDirs();
  if (const char* env = std::getenv("AEROGRASP_OBJECTS_DIR"); env && *env) return dirs.front();
  return DataPath("objects");
}

std::vector<std::string> ObjectNamesIn(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_directory() && fs::exists(entry.path() / "object.yaml")) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> ShippedObjectNames() { return ObjectNamesIn(DataPath("objects")); }

std::string ObjectDetectorPath(const ObjectModel& object) {
  const fs::path onnx = fs::path(object.source).parent_path() / "detector.onnx";
  return fs::exists(onnx) ? onnx.string() : "";
}

Eigen::Vector3d PlacementCentre(const TriangleMesh& mesh_o) {
  return 0.5 * (mesh_o.BoundsMin() + mesh_o.BoundsMax());
}

Eigen::Isometry3d PlaceByCentre(const Eigen::Isometry3d& xMcentre, const TriangleMesh& mesh_o) {
  return xMcentre * Eigen::Translation3d(-PlacementCentre(mesh_o));
}

ObjectModel ObjectModel::Load(const std::string& what) {
  fs::path path(what);
  bool by_name = false;
  if (!fs::exists(path) && path.parent_path().empty() && !what.empty()) {
    for (const std::string& dir : ObjectSearchDirs()) {
      if (fs::exists(fs::path(dir) / what / "object.yaml")) {
        path = fs::path(dir) / what;
        by_name = true;
        break;
      }
    }
    if (!by_name) {
      std::string known = "shipped: " + JoinNames(ShippedObjectNames());
      std::string searched;
      for (const std::string& dir : ObjectSearchDirs()) {
        searched += (searched.empty() ? "" : ", ") + dir;
        if (dir == DataPath("objects")) continue;
        const std::vector<std::string> names = ObjectNamesIn(dir);
        if (!names.empty()) known += "; in " + dir + ": " + JoinNames(names);
      }
      throw ConfigError(what + ": no such file and no object of that name (" + known +
                        "; searched " + searched +
                        "). Bring a mesh in with `aerograsp object import MESH --name NAME`");
    }
  }
  if (fs::is_directory(path)) path /= "object.yaml";
  if (!fs::exists(path)) throw ConfigError(path.string() + ": no such file");
  path = fs::absolute(path).lexically_normal();

  ObjectModel model;
  model.source = path.string();
  const std::string ext = path.extension().string();
  bool have_symmetry = false;
  if (ext == ".yaml" || ext == ".yml") {
    const ConfigNode node = ConfigNode::LoadFile(path.string());
    node.RequireOnlyKeys({"name", "mesh", "mass_kg", "volume_m3", "center_of_mass_m",
                          "inertia_kg_m2", "dimensions_m", "symmetry"});
    model.name = node.GetString("name");
    model.mesh_o = LoadClosedMesh(node.GetPath("mesh"));
    model.mass_kg = node.GetDouble("mass_kg");
    CheckRange(model.source, "mass_kg", model.mass_kg, 1e-3, 20.0, "kg");
    if (node.Has("symmetry")) {
      model.symmetry = ReadSymmetry(node.Child("symmetry"));
      have_symmetry = true;
    }
  } else {
    model.name = path.stem().string();
    model.mesh_o = LoadClosedMesh(path.string());
  }
  model.reference = by_name ? what : model.source;
  const MassProperties mass = ComputeMassProperties(model.mesh_o);
  if (model.mass_kg <= 0.0) {
    model.mass_kg = mass.volume_m3 * kDefaultDensity;
    model.mass_estimated = true;
  }
  model.center_of_mass_o = mass.center_of_mass;
  model.inertia_kg_m2 = mass.inertia_unit_density * (model.mass_kg / mass.volume_m3);
  model.dimensions_m = model.mesh_o.BoundsMax() - model.mesh_o.BoundsMin();
  if (!have_symmetry) model.symmetry = FindMeshSymmetries(model.mesh_o);
  return model;
}

}  // namespace aerograsp
