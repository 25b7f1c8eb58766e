#include "core/object_model.h"

#include <algorithm>
#include <filesystem>

#include "core/config.h"
#include "core/data_dir.h"

namespace aerograsp {
namespace fs = std::filesystem;

std::vector<std::string> ShippedObjectNames() {
  std::vector<std::string> names;
  const fs::path objects = DataPath("objects");
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(objects, ec)) {
    if (entry.is_directory() && fs::exists(entry.path() / "object.yaml")) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

ObjectModel ObjectModel::Load(const std::string& what) {
  fs::path path(what);
  if (!fs::exists(path) && path.parent_path().empty()) {
    path = fs::path(DataPath("objects")) / what;
    if (!fs::exists(path)) {
      std::string names;
      for (const auto& n : ShippedObjectNames()) names += (names.empty() ? "" : ", ") + n;
      throw ConfigError(
          what + ": no such file and no shipped object of that name (shipped: " + names + ")");
    }
  }
  if (fs::is_directory(path)) path /= "object.yaml";
  if (!fs::exists(path)) throw ConfigError(path.string() + ": no such file");

  ObjectModel model;
  model.source = path.string();
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    const ConfigNode node = ConfigNode::LoadFile(path.string());
    node.RequireOnlyKeys({"name", "mesh", "mass_kg", "volume_m3", "center_of_mass_m",
                          "inertia_kg_m2", "dimensions_m"});
    model.name = node.GetString("name");
    model.mesh_o = LoadClosedMesh(node.GetPath("mesh"));
    model.mass_kg = node.GetDouble("mass_kg");
    CheckRange(model.source, "mass_kg", model.mass_kg, 1e-3, 20.0, "kg");
  } else {
    model.name = path.stem().string();
    model.mesh_o = LoadClosedMesh(path.string());
  }
  const MassProperties mass = ComputeMassProperties(model.mesh_o);
  if (model.mass_kg <= 0.0) {
    model.mass_kg = mass.volume_m3 * kDefaultDensity;
    model.mass_estimated = true;
  }
  model.center_of_mass_o = mass.center_of_mass;
  model.dimensions_m = model.mesh_o.BoundsMax() - model.mesh_o.BoundsMin();
  return model;
}

}  // namespace aerograsp
