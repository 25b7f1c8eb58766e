#include "app/calibration/intrinsics_views.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/calibration/calibrate_intrinsics.h"
#include "app/calibration/calibration_samples.h"
#include "app/calibration/calibration_visp.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "calib/intrinsics_calibration.h"
#include "core/config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kOutlierFactor = 3.0;   // a view's error above this times the median...
constexpr double kOutlierFloorPx = 1.0;  // ...and above this is rejected

/// Solves from the accepted views; views whose error stands out are rejected
/// (in `file`) and the rest solved again.
IntrinsicsResult Solve(ViewsFile* file, std::vector<std::size_t>* used) {
  auto accepted = [&] {
    used->clear();
    std::vector<IntrinsicsView> views;
    for (std::size_t i = 0; i < file->views.size(); ++i) {
      if (!file->views[i].accepted) continue;
      used->push_back(i);
      views.push_back({file->views[i].corners});
    }
    return views;
  };
  const int width = file->factory.width, height = file->factory.height;
  IntrinsicsResult result = CalibrateIntrinsics(accepted(), width, height, kMinIntrinsicsViews);
  if (!result.ok) return result;
  const double median_px = Percentile(result.per_view_rms_px, 0.5, 0.0);
  const double limit_px = std::max(kOutlierFloorPx, kOutlierFactor * median_px);
  std::vector<std::size_t> outliers;
  for (std::size_t k = 0; k < used->size(); ++k) {
    if (result.per_view_rms_px[k] > limit_px) outliers.push_back(k);
  }
  if (outliers.empty() || static_cast<int>(used->size() - outliers.size()) < kMinIntrinsicsViews)
    return result;
  for (std::size_t k : outliers) {
    SavedView& v = file->views[(*used)[k]];
    v.accepted = false;
    v.reject_reason =
        fmt::format("reprojection error {:.2f} px in the first solve (limit {:.2f} px)",
                    result.per_view_rms_px[k], limit_px);
  }
  return CalibrateIntrinsics(accepted(), width, height, kMinIntrinsicsViews);
}

void WriteIntrinsicsYaml(const std::string& path, const IntrinsicsResult& r,
                         const CameraIntrinsics& factory, int views_used) {
  YAML::Emitter y;
  y.SetDoublePrecision(10);
  y << YAML::BeginMap;
  y << YAML::Key << "width" << YAML::Value << r.K.width << YAML::Key << "height" << YAML::Value
    << r.K.height;
  y << YAML::Key << "fx_px" << YAML::Value << r.K.fx << YAML::Key << "fy_px" << YAML::Value
    << r.K.fy;
  y << YAML::Key << "cx_px" << YAML::Value << r.K.cx << YAML::Key << "cy_px" << YAML::Value
    << r.K.cy;
  y << YAML::Key << "distortion" << YAML::Value << YAML::Flow
    << std::vector<double>(r.distortion.begin(), r.distortion.end());
  y << YAML::Key << "rms_px" << YAML::Value << r.rms_px << YAML::Key << "views_used" << YAML::Value
    << views_used;
  y << YAML::Key << "factory" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "fx_px"
    << YAML::Value << factory.fx << YAML::Key << "fy_px" << YAML::Value << factory.fy << YAML::Key
    << "cx_px" << YAML::Value << factory.cx << YAML::Key << "cy_px" << YAML::Value << factory.cy
    << YAML::EndMap;
  y << YAML::Key << "camera_xml" << YAML::Value << "camera.xml";
  y << YAML::EndMap;
  std::ofstream out(path);
  out << "# Camera intrinsics from `aerograsp calibrate --intrinsics` (pixels, OpenCV's "
         "pixel-centre convention).\n"
         "# distortion: OpenCV's k1, k2, p1, p2, k3 (k3 held at 0). camera.xml beside this file "
         "holds fx, fy, cx,\n"
         "# cy as ViSP's camera XML without distortion, the model the platform loads (camera.xml "
         "in its YAML).\n"
      << y.c_str() << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace

std::string ViewsPath(const std::string& folder) {
  return (fs::path(folder) / "views.yaml").string();
}

void WriteViewsYaml(const std::string& folder, const ViewsFile& file) {
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "kind" << YAML::Value << "intrinsics";
  y << YAML::Key << "simulated" << YAML::Value << file.simulated;
  y << YAML::Key << "camera_name" << YAML::Value << file.camera_name;
  y << YAML::Key << "factory" << YAML::Value << YAML::Flow << YAML::BeginMap;
  const CameraIntrinsics& K = file.factory;
  y << YAML::Key << "width" << YAML::Value << K.width << YAML::Key << "height" << YAML::Value
    << K.height << YAML::Key << "fx_px" << YAML::Value << K.fx << YAML::Key << "fy_px"
    << YAML::Value << K.fy << YAML::Key << "cx_px" << YAML::Value << K.cx << YAML::Key << "cy_px"
    << YAML::Value << K.cy << YAML::EndMap;
  y << YAML::Key << "board" << YAML::Value;
  EmitTagBoard(file.board, &y);
  y << YAML::Key << "views" << YAML::Value << YAML::BeginSeq;
  for (const SavedView& v : file.views) {
    y << YAML::BeginMap;
    y << YAML::Key << "image" << YAML::Value << v.image;
    y << YAML::Key << "tags_used" << YAML::Value << v.tags_used;
    y << YAML::Key << "accepted" << YAML::Value << v.accepted;
    y << YAML::Key << "reject_reason" << YAML::Value << v.reject_reason;
    y << YAML::Key << "corners" << YAML::Value;
    EmitCorners(v.corners, &y);
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  const std::string path = ViewsPath(folder);
  std::ofstream out(path);
  out << "# aerograsp intrinsics views: re-solve with `aerograsp calibrate --resolve DIR`.\n"
      << y.c_str() << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

ViewsFile ReadViewsYaml(const std::string& folder) {
  const std::string path = ViewsPath(folder);
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"kind", "simulated", "camera_name", "factory", "board", "views"});
  if (root.GetString("kind") != "intrinsics") root.Fail("kind", "expected 'intrinsics'");
  ViewsFile file;
  file.simulated = root.GetBool("simulated", false);
  file.camera_name = root.GetString("camera_name", file.camera_name);
  const ConfigNode factory = root.Child("factory");
  factory.RequireOnlyKeys({"width", "height", "fx_px", "fy_px", "cx_px", "cy_px"});
  file.factory.width = factory.GetInt("width");
  file.factory.height = factory.GetInt("height");
  file.factory.fx = factory.GetDouble("fx_px");
  file.factory.fy = factory.GetDouble("fy_px");
  file.factory.cx = factory.GetDouble("cx_px");
  file.factory.cy = factory.GetDouble("cy_px");
  file.factory.Validate(path, "factory.");
  file.board = TagBoardConfig::FromNode(root.Child("board"));
  file.board.Validate(path, "board.");
  const YAML::Node all = YAML::LoadFile(path)["views"];
  if (!all || !all.IsSequence()) root.Fail("views", "expected a list of views");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string where = "views[" + std::to_string(i) + "]";
    try {
      SavedView v;
      v.image = all[i]["image"].as<std::string>();
      v.tags_used = all[i]["tags_used"].as<int>(0);
      v.accepted = all[i]["accepted"].as<bool>();
      v.reject_reason = all[i]["reject_reason"].as<std::string>("");
      v.corners = ReadCorners(all[i]["corners"], root, where + ".corners");
      file.views.push_back(std::move(v));
    } catch (const YAML::Exception& e) {
      root.Fail(where, std::string("malformed: ") + e.what());
    }
  }
  return file;
}

void SolveIntrinsicsAndReport(const std::string& folder, ViewsFile* file, std::ostream& out) {
  int not_usable = 0;
  for (const SavedView& v : file->views) not_usable += v.accepted ? 0 : 1;
  const int usable = static_cast<int>(file->views.size()) - not_usable;
  if (usable < kMinIntrinsicsViews) {
    WriteViewsYaml(folder, *file);
    throw std::runtime_error(
        fmt::format("{}: only {} usable views of the board (at least {} needed; {} rejected: not "
                    "seen or partly seen); the "
                    "views are kept in {}",
                    folder, usable, kMinIntrinsicsViews, not_usable, ViewsPath(folder)));
  }
  std::vector<std::size_t> used;
  const IntrinsicsResult r = Solve(file, &used);
  WriteViewsYaml(folder, *file);  // with the outliers' reasons
  if (!r.ok) throw std::runtime_error(folder + ": the intrinsics solve failed: " + r.message);
  const int rejected = static_cast<int>(file->views.size() - used.size());
  out << fmt::format("views: {} used, {} rejected (kept in {})\n", used.size(), rejected,
                     ViewsPath(folder));
  for (std::size_t i = 0; i < file->views.size(); ++i) {
    if (!file->views[i].accepted)
      out << fmt::format("  view {:3d} rejected: {}\n", i, file->views[i].reject_reason);
  }
  out << fmt::format("{:>6} {:>6} {:>8}\n", "view", "tags", "rms px");
  for (std::size_t k = 0; k < used.size(); ++k) {
    out << fmt::format("{:>6} {:>6} {:>8.3f}\n", used[k], file->views[used[k]].tags_used,
                       r.per_view_rms_px[k]);
  }
  const CameraIntrinsics& F = file->factory;
  const std::string factory_name = file->simulated ? "factory (truth)" : "factory";
  out << fmt::format("{:<10} {:>12} {:>16} {:>12}\n", "", "recovered", factory_name, "difference");
  const std::pair<const char*, std::pair<double, double>> rows[] = {{"fx (px)", {r.K.fx, F.fx}},
                                                                    {"fy (px)", {r.K.fy, F.fy}},
                                                                    {"cx (px)", {r.K.cx, F.cx}},
                                                                    {"cy (px)", {r.K.cy, F.cy}}};
  for (const auto& [name, values] : rows) {
    out << fmt::format("{:<10} {:>12.3f} {:>16.3f} {:>+12.3f}\n", name, values.first, values.second,
                       values.first - values.second);
  }
  out << fmt::format("distortion k1 k2 p1 p2 k3: {:.5f} {:.5f} {:.5f} {:.5f} {:.5f}\n",
                     r.distortion[0], r.distortion[1], r.distortion[2], r.distortion[3],
                     r.distortion[4]);
  out << fmt::format("reprojection error: {:.3f} px rms over {} views\n", r.rms_px, used.size());

  const std::string yaml_path = (fs::path(folder) / "intrinsics.yaml").string();
  WriteIntrinsicsYaml(yaml_path, r, F, static_cast<int>(used.size()));
  SaveCameraXml(r.K, file->camera_name, (fs::path(folder) / "camera.xml").string());
  nlohmann::json rejected_views = nlohmann::json::array();
  for (std::size_t i = 0; i < file->views.size(); ++i) {
    if (!file->views[i].accepted)
      rejected_views.push_back({{"view", i}, {"reason", file->views[i].reject_reason}});
  }
  nlohmann::json summary = {{"views_used", used.size()},
                            {"views_rejected", rejected},
                            {"rms_px", r.rms_px},
                            {"per_view_rms_px", r.per_view_rms_px},
                            {"views_used_index", used},
                            {"rejected", rejected_views},
                            {"width", r.K.width},
                            {"height", r.K.height},
                            {"fx", r.K.fx},
                            {"fy", r.K.fy},
                            {"cx", r.K.cx},
                            {"cy", r.K.cy},
                            {"dist", r.distortion},
                            {"factory",
                             {{"is_truth", file->simulated},
                              {"fx", F.fx},
                              {"fy", F.fy},
                              {"cx", F.cx},
                              {"cy", F.cy},
                              {"difference_px",
                               {{"fx", r.K.fx - F.fx},
                                {"fy", r.K.fy - F.fy},
                                {"cx", r.K.cx - F.cx},
                                {"cy", r.K.cy - F.cy}}}}}};
  WriteSummaryFile(folder, summary.dump(2));
  out << fmt::format("wrote {}, {}/camera.xml, {}/summary.json\n", yaml_path, folder, folder);
}

bool IsIntrinsicsFolder(const std::string& folder) { return fs::exists(ViewsPath(folder)); }

void ResolveIntrinsics(const std::string& folder, std::ostream& out) {
  ViewsFile file = ReadViewsYaml(folder);
  // Views rejected by the last solve's outlier test get another chance.
  for (SavedView& v : file.views) {
    if (!v.accepted && v.reject_reason.rfind("reprojection error", 0) == 0) {
      v.accepted = true;
      v.reject_reason.clear();
    }
  }
  SolveIntrinsicsAndReport(folder, &file, out);
}

}  // namespace aerograsp
