#include "app/commands/object_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "app/cli_checks.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/mesh.h"
#include "core/mesh_repair.h"
#include "core/object_model.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

struct Unit {
  const char* name;
  const char* long_name;
  double metres;
};
constexpr Unit kUnits[] = {
    {"m", "metres", 1.0}, {"cm", "centimetres", 0.01}, {"mm", "millimetres", 0.001}};

const Unit& FindUnit(const std::string& name) {
  for (const Unit& unit : kUnits) {
    if (name == unit.name) return unit;
  }
  throw ConfigError("--units: '" + name + "' is not one of m, cm, mm");
}

void CheckName(const std::string& name) {
  const bool ok =
      !name.empty() && name.size() <= 64 && name.front() != '-' && name.front() != '.' &&
      std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
      });
  if (!ok) {
    throw ConfigError("--name: '" + name +
                      "' is not a usable object name (1 to 64 letters, digits, '_', '-' or '.', "
                      "not starting with '-' or '.')");
  }
}

std::string Vec(const Eigen::Vector3d& v, const char* format = "{:.6f}") {
  const auto clean = [](double x) { return std::abs(x) < 5e-13 ? 0.0 : x; };
  return fmt::format(std::string("[") + format + ", " + format + ", " + format + "]", clean(v.x()),
                     clean(v.y()), clean(v.z()));
}

/// The size check: the longest side in metres within the config's range, or a
/// refusal saying the size seen and the units that would make sense.
void CheckSize(const std::string& path, const TriangleMesh& raw, const Unit& unit,
               const ObjectImportConfig& config) {
  const Eigen::Vector3d extent = raw.BoundsMax() - raw.BoundsMin();
  const double longest_m = extent.maxCoeff() * unit.metres;
  const double shortest_m = extent.minCoeff() * unit.metres;
  if (longest_m >= config.min_extent_m && longest_m <= config.max_extent_m) {
    if (shortest_m < config.min_thickness_m) {
      throw MeshError(path + ": the mesh is " + fmt::format("{:.4g}", shortest_m) +
                      " m thin along its thinnest side (at most " +
                      fmt::format("{:.4g}", config.min_thickness_m) +
                      " m is refused): a sheet, not a solid the arms can grasp");
    }
    return;
  }
  // The units that would give a plausible size, millimetres (CAD's usual) first.
  std::string hint;
  for (auto other = std::rbegin(kUnits); other != std::rend(kUnits); ++other) {
    const double size = extent.maxCoeff() * other->metres;
    if (other->metres != unit.metres && size >= config.min_extent_m &&
        size <= config.max_extent_m) {
      hint += fmt::format("{} in {}, give --units {} ({:.4g} m)",
                          hint.empty() ? "; if the file is" : "; if", other->long_name, other->name,
                          size);
    }
  }
  throw MeshError(fmt::format(
      "{}: the mesh is {:.4g} x {:.4g} x {:.4g} in the file's units, {:.4g} m across read as {} "
      "(--units {}): an object must be {:.4g} to {:.4g} m across{}",
      path, extent.x(), extent.y(), extent.z(), longest_m, unit.long_name, unit.name,
      config.min_extent_m, config.max_extent_m, hint));
}

std::string SymmetryYaml(const ObjectSymmetry& symmetry) {
  std::string text =
      "# The rotations that map the object (shape and vertex colours) onto itself, about\n"
      "# center_m: p -> center + R (p - center). Found by `object import` (docs/objects.md);\n"
      "# remove rotations a texture breaks. rotations_wxyz: quaternions, the identity first.\n"
      "symmetry:\n";
  text += "  center_m: " + Vec(symmetry.center_o) + "\n";
  if (symmetry.continuous_axis_o) {
    text += "  continuous_axis: " + Vec(*symmetry.continuous_axis_o) +
            "  # any turn about this axis through center_m\n";
  }
  text += "  rotations_wxyz: [\n";
  for (std::size_t i = 0; i < symmetry.rotations.size(); ++i) {
    const Eigen::Quaterniond q(symmetry.rotations[i]);
    const Eigen::AngleAxisd aa(symmetry.rotations[i]);
    const auto c = [](double x) { return std::abs(x) < 5e-10 ? 0.0 : x; };
    text += fmt::format("    {:.9f}, {:.9f}, {:.9f}, {:.9f}{}  # ", c(q.w()), c(q.x()), c(q.y()),
                        c(q.z()), i + 1 < symmetry.rotations.size() ? "," : "");
    text += i == 0 ? "identity\n"
                   : fmt::format("{:.0f} deg about {}\n", aa.angle() * 180.0 / M_PI,
                                 Vec(aa.axis(), "{:.4f}"));
  }
  text += "  ]\n";
  return text;
}

}  // namespace

void ObjectImportConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "min_extent_m", min_extent_m, 1e-6, max_extent_m, "m");
  CheckRange(source, prefix + "max_extent_m", max_extent_m, min_extent_m, 100.0, "m");
  CheckRange(source, prefix + "min_thickness_m", min_thickness_m, 0.0, min_extent_m, "m");
  CheckRange(source, prefix + "merge_distance_ratio", merge_distance_ratio, 0.0, 1e-3, "");
  symmetry.Validate(source, prefix + "symmetry.");
}

ObjectImportConfig ObjectImportConfig::Load(const std::string& path) {
  const ConfigNode node = ConfigNode::LoadFile(path);
  node.RequireOnlyKeys(
      {"min_extent_m", "max_extent_m", "min_thickness_m", "merge_distance_ratio", "symmetry"});
  ObjectImportConfig c;
  c.min_extent_m = node.GetDouble("min_extent_m", c.min_extent_m);
  c.max_extent_m = node.GetDouble("max_extent_m", c.max_extent_m);
  c.min_thickness_m = node.GetDouble("min_thickness_m", c.min_thickness_m);
  c.merge_distance_ratio = node.GetDouble("merge_distance_ratio", c.merge_distance_ratio);
  if (node.Has("symmetry")) {
    const ConfigNode s = node.Child("symmetry");
    s.RequireOnlyKeys({"tolerance_ratio", "surface_samples", "max_vertices", "max_outlier_fraction",
                       "max_axis_order", "seed"});
    SymmetryOptions& o = c.symmetry;
    o.tolerance_ratio = s.GetDouble("tolerance_ratio", o.tolerance_ratio);
    o.surface_samples = s.GetInt("surface_samples", o.surface_samples);
    o.max_vertices = s.GetInt("max_vertices", o.max_vertices);
    o.max_outlier_fraction = s.GetDouble("max_outlier_fraction", o.max_outlier_fraction);
    o.max_axis_order = s.GetInt("max_axis_order", o.max_axis_order);
    const int seed = s.GetInt("seed", static_cast<int>(o.seed));
    CheckRange(path, "symmetry.seed", seed, 0, 2147483647, "");
    o.seed = static_cast<std::uint64_t>(seed);
  }
  c.Validate(path, "");
  return c;
}

std::string RunObjectImport(const ObjectImportOptions& options, std::ostream& out) {
  CheckName(options.name);
  const Unit& unit = FindUnit(options.units);
  const ObjectImportConfig config = ObjectImportConfig::Load(
      options.config_path.empty() ? DataPath("config/object_import.yaml") : options.config_path);
  if (options.mass_kg != 0.0) {
    CheckRange("--mass", "mass", options.mass_kg, 1e-3, 20.0, "kg");
  }
  const fs::path dir =
      fs::absolute(options.objects_dir.empty() ? DefaultObjectImportDir() : options.objects_dir)
          .lexically_normal();
  const fs::path folder = dir / options.name;
  // One object per name across the folders searched by name.
  for (const std::string& searched : ObjectSearchDirs()) {
    const fs::path other = fs::absolute(fs::path(searched) / options.name).lexically_normal();
    if (other != folder && fs::exists(other / "object.yaml")) {
      throw ConfigError("--name: '" + options.name + "' is already an object in " + searched +
                        " (commands find objects by name there): choose another name");
    }
  }
  if (fs::exists(folder) && !options.overwrite) {
    throw ConfigError(folder.string() + ": already exists; --overwrite replaces it");
  }

  // Read, size, repair (in the file's units, so that messages name places the
  // user can find in the file), then scale to metres.
  const std::string& path = options.mesh_path;
  TriangleMesh mesh = LoadMeshAnyScale(path);
  const std::size_t read_vertices = mesh.vertices.size(), read_triangles = mesh.triangles.size();
  CheckSize(path, mesh, unit, config);
  const double diagonal = (mesh.BoundsMax() - mesh.BoundsMin()).norm();
  const MeshRepairReport repairs =
      RepairMesh(&mesh, config.merge_distance_ratio * diagonal, path, unit.name);
  for (Eigen::Vector3d& v : mesh.vertices) v *= unit.metres;

  const MassProperties mass = ComputeMassProperties(mesh);
  const Eigen::Vector3d extent = mesh.BoundsMax() - mesh.BoundsMin();
  const bool estimated = options.mass_kg == 0.0;
  const double mass_kg =
      estimated ? mass.volume_m3 * ObjectModel::kDefaultDensity : options.mass_kg;
  if (estimated && !(mass_kg >= 1e-3 && mass_kg <= 20.0)) {
    throw ConfigError(fmt::format(
        "{}: {:.4g} m^3 at {:.0f} kg/m^3 is {:.4g} kg, outside [0.001, 20] kg: give the "
        "object's mass with --mass",
        path, mass.volume_m3, ObjectModel::kDefaultDensity, mass_kg));
  }
  const Eigen::Matrix3d inertia = mass.inertia_unit_density * (mass_kg / mass.volume_m3);
  const auto t0 = std::chrono::steady_clock::now();
  const ObjectSymmetry symmetry = FindMeshSymmetries(mesh, config.symmetry);
  const double symmetry_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Written beside, then moved into place: no half-written object under its name.
  fs::create_directories(dir);
  const fs::path staging = dir / ("." + options.name + ".importing");
  fs::remove_all(staging);
  fs::create_directories(staging);
  try {
    SaveMeshPly(mesh, (staging / (options.name + ".ply")).string());
    std::ofstream yaml(staging / "object.yaml");
    yaml << fmt::format(
        "# aerograsp object model '{name}', imported by `aerograsp object import` from\n"
        "# {source} (read in {units}, stored in metres).\n"
        "# Frame o: the frame of that file, not re-centred: poses (--init-pose, ground truth,\n"
        "# outputs) refer to it. Commands that place the object themselves put its\n"
        "# bounding-box centre, {bbox} m in o, where they are asked.\n"
        "# {mass_note}\n"
        "name: {name}\n"
        "mesh: {name}.ply\n"
        "mass_kg: {mass:.6g}\n"
        "volume_m3: {volume:.9f}\n"
        "center_of_mass_m: {com}\n"
        "# Inertia about the centre of mass, axes of frame o, kg m^2 (rows of the 3x3 tensor).\n"
        "inertia_kg_m2: [{i0}, {i1}, {i2}]\n"
        "dimensions_m: {dims}\n",
        fmt::arg("name", options.name), fmt::arg("source", fs::absolute(path).string()),
        fmt::arg("units", unit.long_name), fmt::arg("bbox", Vec(PlacementCentre(mesh))),
        fmt::arg("mass_note",
                 estimated ? fmt::format("mass_kg is an estimate: the volume at {:.0f} kg/m^3; "
                                         "centre of mass and inertia at uniform density.",
                                         ObjectModel::kDefaultDensity)
                           : std::string("mass_kg as given (--mass); centre of mass and inertia "
                                         "at uniform density.")),
        fmt::arg("mass", mass_kg), fmt::arg("volume", mass.volume_m3),
        fmt::arg("com", Vec(mass.center_of_mass)),
        fmt::arg("i0", Vec(inertia.row(0).transpose(), "{:.6e}")),
        fmt::arg("i1", Vec(inertia.row(1).transpose(), "{:.6e}")),
        fmt::arg("i2", Vec(inertia.row(2).transpose(), "{:.6e}")), fmt::arg("dims", Vec(extent)));
    yaml << SymmetryYaml(symmetry);
    yaml.close();
    if (!yaml) throw ConfigError((staging / "object.yaml").string() + ": cannot be written");
    ObjectModel::Load(staging.string());  // it loads as every command will load it
    fs::remove_all(folder);
    fs::rename(staging, folder);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    throw;
  }

  out << fmt::format("object import: {} -> {}\n", path, folder.string());
  out << fmt::format("  read: {} vertices, {} triangles, in {}\n", read_vertices, read_triangles,
                     unit.long_name);
  const std::vector<std::string> lines = repairs.Lines();
  if (lines.empty()) out << "  repairs: none needed (closed, consistently oriented, outward)\n";
  for (const std::string& line : lines) out << "  repaired: " << line << "\n";
  out << fmt::format("  closed solid: {} vertices, {} triangles, {} shell{}\n",
                     mesh.vertices.size(), mesh.triangles.size(), repairs.shells,
                     repairs.shells == 1 ? "" : "s");
  out << fmt::format(
      "  size: {:.4f} x {:.4f} x {:.4f} m; bounding-box centre {} m in the file's "
      "frame (kept as frame o)\n",
      extent.x(), extent.y(), extent.z(), Vec(PlacementCentre(mesh), "{:.4f}"));
  out << fmt::format("  volume {:.6g} m^3, centre of mass {} m\n", mass.volume_m3,
                     Vec(mass.center_of_mass, "{:.4f}"));
  out << (estimated ? fmt::format("  mass {:.4g} kg: estimated at {:.0f} kg/m^3 (give --mass to "
                                  "set it)\n",
                                  mass_kg, ObjectModel::kDefaultDensity)
                    : fmt::format("  mass {:.4g} kg (given)\n", mass_kg));
  out << fmt::format("  inertia about the centre of mass, diagonal {} kg m^2\n",
                     Vec(inertia.diagonal(), "{:.4e}"));
  out << fmt::format("  symmetry: {} ({:.0f} ms)\n", DescribeSymmetry(symmetry), 1e3 * symmetry_s);
  bool searched = false;
  for (const std::string& d : ObjectSearchDirs()) {
    searched = searched || fs::absolute(d).lexically_normal() == dir;
  }
  if (searched) {
    out << fmt::format(
        "  use it as: --object {} (plan {}, record/replay/dataset/mission --object {})\n",
        options.name, options.name, options.name);
  } else {
    out << fmt::format(
        "  {} is not searched by name: set AEROGRASP_OBJECTS_DIR={} to use --object {}, or give "
        "the folder {}\n",
        dir.string(), dir.string(), options.name, folder.string());
  }
  return folder.string();
}

void RunObjectShow(const std::string& what, bool folder_only, std::ostream& out) {
  const ObjectModel model = ObjectModel::Load(what);
  const fs::path source(model.source);
  const bool is_folder = source.filename() == "object.yaml";
  if (folder_only) {
    if (!is_folder) {
      throw ConfigError(model.source +
                        ": a mesh file, not an object folder: import it first "
                        "(aerograsp object import MESH --name NAME)");
    }
    out << source.parent_path().string() << "\n";
    return;
  }
  const Eigen::Vector3d& d = model.dimensions_m;
  out << fmt::format("object {}: {}\n", model.name, model.source);
  out << fmt::format(
      "  mesh: {} vertices, {} triangles{}; {:.4f} x {:.4f} x {:.4f} m, "
      "bounding-box centre {} m in o\n",
      model.mesh_o.vertices.size(), model.mesh_o.triangles.size(),
      model.mesh_o.colors.empty() ? ", no colours" : ", vertex colours", d.x(), d.y(), d.z(),
      Vec(PlacementCentre(model.mesh_o), "{:.4f}"));
  out << fmt::format("  mass {:.4g} kg{}, centre of mass {} m\n", model.mass_kg,
                     model.mass_estimated ? " (estimated from the volume)" : "",
                     Vec(model.center_of_mass_o, "{:.4f}"));
  out << "  symmetry: " << DescribeSymmetry(model.symmetry) << "\n";
  const std::string detector = ObjectDetectorPath(model);
  out << "  detector: "
      << (!detector.empty()
              ? detector
              : "none (train one: scripts/train_detectors.sh " + model.reference + ")")
      << "\n";
}

void AddObjectImportOptions(CLI::App* cmd, ObjectImportOptions* o) {
  std::vector<std::string> units;
  for (const Unit& unit : kUnits) units.push_back(unit.name);
  cmd->add_option("mesh", o->mesh_path, "Mesh file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--name", o->name, "Object name (--object NAME)")->required();
  cmd->add_option("--units", o->units, "Length unit of the file")
      ->capture_default_str()
      ->check(CLI::IsMember(units));
  cmd->add_option("--mass", o->mass_kg, "Mass, kg [the volume at 300 kg/m^3, an estimate]")
      ->check(cli::Range(1e-6, 1e4));
  cmd->add_option("--objects-dir", o->objects_dir,
                  "Folder to store it in [$AEROGRASP_OBJECTS_DIR, else data/objects]");
  cmd->add_option("--config", o->config_path, "Import settings [data/config/object_import.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--overwrite", o->overwrite, "Replace an object of that name in the folder");
}

void AddObjectShowOptions(CLI::App* cmd, ObjectShowOptions* o) {
  cmd->add_option("object", o->object, "Object name or path")->required();
  cmd->add_flag("--folder", o->folder_only, "Print the object's folder only");
}

}  // namespace aerograsp
