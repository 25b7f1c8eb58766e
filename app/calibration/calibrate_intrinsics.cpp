#include "app/calibration/calibrate_intrinsics.h"

#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_samples.h"
#include "app/calibration/interrupt_guard.h"
#include "app/calibration/tag_board_mesh.h"
#include "app/report/progress.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "calib/intrinsics_calibration.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "core/transforms.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr int kMinViews = 4;
constexpr double kMinBoardFraction = 0.5;  // of the board's tags seen
constexpr double kOutlierFactor = 3.0;     // a view's error above this times the median...
constexpr double kOutlierFloorPx = 1.0;    // ...and above this is rejected
constexpr double kViewStep_s = 0.1;       // simulated time between views (the hand moves the board)
constexpr double kStillPx = 1.0;          // a hand-held board is still: no corner moved more (px)
constexpr int kMaxMissedFrames = 30;      // frames in a row the camera may fail to deliver
constexpr double kHeldDistance_m = 0.45;  // simulated: the board's rest pose in front of the camera

struct View {
  std::string image;  // relative to the output folder
  int tags_used = 0;
  bool accepted = false;
  std::string reject_reason;
  std::vector<BoardCorner> corners;
};

/// Board poses cMt in front of the camera that keep the whole board in the
/// image: distance 0.28-0.55 m, tilt 20-45 deg about an axis in the board's
/// plane that turns by the golden angle from view to view (so any few views
/// hold well separated tilts: Zhang's method needs non-parallel boards), a
/// roll of +-30 deg, the centre anywhere in the image (corners near the image
/// edges constrain the principal point and the distortion).
std::vector<Eigen::Isometry3d> PlanBoardViews(const CameraIntrinsics& K,
                                              const TagBoardConfig& board, int count,
                                              std::uint64_t seed) {
  FastRandom rng(seed);
  const Eigen::Vector2d half = 0.5 * board.Size();
  const Eigen::Vector3d outline_t[4] = {{-half.x(), -half.y(), 0},
                                        {half.x(), -half.y(), 0},
                                        {half.x(), half.y(), 0},
                                        {-half.x(), half.y(), 0}};
  const double margin_px = 0.02 * K.width;
  const double golden_rad = M_PI * (3.0 - std::sqrt(5.0));
  std::vector<Eigen::Isometry3d> views;
  for (int i = 0; i < count; ++i) {
    for (int attempt = 0; attempt < 2000; ++attempt) {
      const double z_m = rng.Uniform(0.28, 0.55);
      const double tilt_rad = rng.Uniform(20.0, 45.0) * kDegToRad;
      const double axis_rad = i * golden_rad + rng.Uniform(-0.3, 0.3);
      const double roll_rad = rng.Uniform(-30.0, 30.0) * kDegToRad;
      const double u = rng.Uniform(0.0, K.width), v = rng.Uniform(0.0, K.height);
      Eigen::Isometry3d cMt = Eigen::Isometry3d::Identity();
      // z_t along +z_c tilted: the printed face (looking along -z_t) faces the camera.
      cMt.linear() = (Eigen::AngleAxisd(
                          tilt_rad, Eigen::Vector3d(std::cos(axis_rad), std::sin(axis_rad), 0.0)) *
                      Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()))
                         .toRotationMatrix();
      cMt.translation() = K.Unproject(u, v, z_m);
      bool in_view = true;
      for (const Eigen::Vector3d& p_t : outline_t) {
        const Eigen::Vector3d p_c = cMt * p_t;
        const Eigen::Vector2d px = K.Project(p_c);
        in_view = in_view && p_c.z() > 0.2 && px.x() > margin_px && px.y() > margin_px &&
                  px.x() < K.width - margin_px && px.y() < K.height - margin_px;
      }
      if (in_view) {
        views.push_back(cMt);
        break;
      }
    }
  }
  return views;
}

struct ViewsFile {
  TagBoardConfig board;
  CameraIntrinsics factory;  // the camera's own intrinsics; in simulation the truth
  std::string camera_name{
      "Camera"};  // the platform's name for it in camera XML (platform.h: camera_name)
  bool simulated = false;
  std::vector<View> views;
};

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
  for (const View& v : file.views) {
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
  file.factory.Validate(path + ": factory");
  file.board = TagBoardConfig::FromNode(root.Child("board"));
  file.board.Validate(path, "board.");
  const YAML::Node all = YAML::LoadFile(path)["views"];
  if (!all || !all.IsSequence()) root.Fail("views", "expected a list of views");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string where = "views[" + std::to_string(i) + "]";
    try {
      View v;
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
  IntrinsicsResult result = CalibrateIntrinsics(accepted(), width, height, kMinViews);
  if (!result.ok) return result;
  const double median_px = Percentile(result.per_view_rms_px, 0.5, 0.0);
  const double limit_px = std::max(kOutlierFloorPx, kOutlierFactor * median_px);
  std::vector<std::size_t> outliers;
  for (std::size_t k = 0; k < used->size(); ++k) {
    if (result.per_view_rms_px[k] > limit_px) outliers.push_back(k);
  }
  if (outliers.empty() || static_cast<int>(used->size() - outliers.size()) < kMinViews)
    return result;
  for (std::size_t k : outliers) {
    View& v = file->views[(*used)[k]];
    v.accepted = false;
    v.reject_reason =
        fmt::format("reprojection error {:.2f} px in the first solve (limit {:.2f} px)",
                    result.per_view_rms_px[k], limit_px);
  }
  return CalibrateIntrinsics(accepted(), width, height, kMinViews);
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

void SolveAndReport(const std::string& folder, ViewsFile* file, std::ostream& out) {
  int not_usable = 0;
  for (const View& v : file->views) not_usable += v.accepted ? 0 : 1;
  const int usable = static_cast<int>(file->views.size()) - not_usable;
  if (usable < kMinViews) {
    WriteViewsYaml(folder, *file);
    throw std::runtime_error(
        fmt::format("{}: only {} usable views of the board (at least {} needed; {} rejected: not "
                    "seen or partly seen); the "
                    "views are kept in {}",
                    folder, usable, kMinViews, not_usable, ViewsPath(folder)));
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

/// A line waiting on `in` (Enter or q), read without blocking: std::cin
/// through poll() on its descriptor, other streams by what they hold. A closed
/// standard input (a script's /dev/null) is read once and ignored after.
class StopKey {
 public:
  explicit StopKey(std::istream& in) : in_(in) {}
  bool Pressed() {
    if (closed_) return false;
    if (&in_ == &std::cin) {
      pollfd fd{STDIN_FILENO, POLLIN, 0};
      if (poll(&fd, 1, 0) <= 0 || !(fd.revents & (POLLIN | POLLHUP))) return false;
    } else if (in_.rdbuf()->in_avail() <= 0) {
      return false;
    }
    std::string line;
    if (!std::getline(in_, line)) {
      closed_ = true;
      return false;
    }
    return true;
  }

 private:
  std::istream& in_;
  bool closed_ = false;
};

/// The board's tilt about the camera's x and y axes, deg (0 facing the camera).
void BoardTilt(const Eigen::Isometry3d& cMt, double* tilt_x_deg, double* tilt_y_deg) {
  const Eigen::Vector3d n_c = cMt.linear().col(2);
  *tilt_x_deg = std::atan2(-n_c.y(), n_c.z()) / kDegToRad;
  *tilt_y_deg = std::atan2(n_c.x(), n_c.z()) / kDegToRad;
}

}  // namespace

IntrinsicsHardware::~IntrinsicsHardware() {
  camera_.reset();  // it renders the world
  world_.reset();
}

void IntrinsicsHardware::WaitForFrame() {
  if (!world_) return;
  world_->Step(1.0 / config_.camera.fps);
  if (hand_) hand_(*this, world_->now_s());
}

std::unique_ptr<IntrinsicsHardware> OpenIntrinsicsHardware(const std::string& hardware_path,
                                                           const std::string& world_path,
                                                           std::uint64_t seed, std::ostream& out) {
  std::unique_ptr<IntrinsicsHardware> hw(new IntrinsicsHardware());
  hw->config_ = HardwareConfig::Load(hardware_path);
  if (!world_path.empty()) hw->config_.world = world_path;
  const HardwareConfig& config = hw->config_;
  if (config.camera.backend == "replay") {
    throw ConfigError(fmt::format(
        "{}: camera.backend: 'replay': a recording cannot follow the coverage feedback; "
        "re-solve saved views with `calibrate --resolve DIR`",
        config.source));
  }
  const CalibrationRig rig = CalibrationRig::Load(hardware_path);
  hw->board_ = rig.mount == "hand" ? rig.board : IntrinsicsBoard();
  if (config.camera.backend == "sim") {
    WorldConfig world_config = WorldConfig::Load(config.world);
    world_config.platform = config.platform;
    hw->world_ = std::make_unique<World>(world_config, seed);
    hw->camera_name_ = hw->world_->platform().config().camera_name;
    // The simulated rig: the board held in front of the camera, facing it.
    hw->board_attachment_ = hw->world_->AttachToCamera(
        MakeBoardRenderMesh(hw->board_, 4000.0),
        MakeTransform(Eigen::Vector3d(0.0, 0.0, kHeldDistance_m), Eigen::Vector3d::Zero()));
  } else {
    hw->camera_name_ = Platform::Load(config.platform).config().camera_name;
  }
  out << fmt::format("devices ({}):\n", config.source);
  try {
    hw->camera_ = OpenCamera(config.camera, hw->world_.get());
  } catch (const std::exception& e) {
    out << "  camera   FAILED: " << e.what() << "\n";
    throw HardwareError(
        fmt::format("{}: the camera did not open; nothing was recorded:\n  camera ({}): {}",
                    config.source, config.camera.backend, e.what()));
  }
  out << fmt::format("  {:<8} ok: {}{}\n", "camera", config.camera.backend,
                     hw->world_ ? " (simulated, the board held in its world)" : "");
  return hw;
}

void RunHandHeldIntrinsics(const CalibrateCommandOptions& options, IntrinsicsHardware& hw,
                           std::istream& in, std::ostream& out) {
  if (options.out_dir.empty() && !options.dry_run)
    throw ConfigError("--out: an output folder is required");
  CheckRange("command line", "--poses", options.poses, kMinViews, 100, "");
  const CoverageConfig coverage_config;
  RgbdCamera& camera = hw.camera();
  ViewsFile file;
  file.board = hw.board();
  file.factory = camera.intrinsics();
  file.simulated = hw.world() != nullptr;
  file.camera_name = hw.camera_name();
  const CameraIntrinsics& K = file.factory;
  const int board_tags = file.board.rows * file.board.cols;

  out << "pre-flight:\n";
  RgbdFrame frame;
  const bool got = camera.Grab(&frame);
  const bool size_ok = got && frame.color.width == K.width && frame.color.height == K.height;
  out << fmt::format(
      "  {:<8} camera: {}\n", size_ok && K.fx > 0.0 ? "ok" : "FAILED",
      got ? fmt::format("frame {} of {}x{} (intrinsics {}x{}, fx {:.1f} fy {:.1f})", frame.index,
                        frame.color.width, frame.color.height, K.width, K.height, K.fx, K.fy)
          : std::string("no frame: the stream is not running"));
  if (!size_ok || !(K.fx > 0.0)) {
    throw HardwareError(fmt::format("{}: pre-flight failed: camera ({}): {}", hw.config().source,
                                    hw.config().camera.backend,
                                    got ? "its frames are not of its intrinsics' size"
                                        : "no frame: the stream is not running"));
  }
  out << fmt::format(
      "hold the {} x {} board of {:.0f} mm tags (all {} tags in view) still in each pose; a "
      "sample is taken when it adds to the coverage: every cell of a {} x {} grid of the image, "
      "tilts about x and y beyond +-{:.0f} deg, at least {} samples. Enter or q: solve now; "
      "Ctrl-C: stop (the samples kept)\n",
      file.board.rows, file.board.cols, 1e3 * file.board.tag_size_m, board_tags,
      coverage_config.grid_cols, coverage_config.grid_rows, coverage_config.min_tilt_deg,
      options.poses);
  if (!options.out_dir.empty()) {  // the board to print
    fs::create_directories(options.out_dir);
    WriteBoardSvg(file.board, (fs::path(options.out_dir) / "board.svg").string());
    out << fmt::format("the board to print: {}/board.svg\n", options.out_dir);
  }
  if (options.dry_run) {
    out << "dry run: nothing was recorded\n";
    return;
  }
  fs::create_directories(fs::path(options.out_dir) / "views");
  TagDetector detector(file.board.family);
  Coverage coverage = EmptyCoverage(coverage_config);
  StopKey key(in);
  const InterruptGuard interrupt;
  std::vector<Eigen::Vector2d> previous_px;
  int missed = 0;
  std::string stopped_by;
  while (stopped_by.empty()) {
    if (InterruptGuard::Interrupted()) {
      stopped_by = "Ctrl-C";
      break;
    }
    if (key.Pressed()) {
      stopped_by = "the keyboard";
      break;
    }
    hw.WaitForFrame();
    if (!camera.Grab(&frame)) {
      if (++missed < kMaxMissedFrames) continue;
      WriteViewsYaml(options.out_dir, file);
      throw HardwareError(fmt::format(
          "{}: camera ({}): no frame {} times in a row: the camera stopped; the {} samples "
          "taken are kept in {} (solve them with `calibrate --resolve {}`)",
          hw.config().source, hw.config().camera.backend, missed, file.views.size(),
          ViewsPath(options.out_dir), options.out_dir));
    }
    missed = 0;
    const std::vector<TagDetection> detections = detector.Detect(frame.color);
    int tags_used = 0;
    std::vector<BoardCorner> corners = MatchBoardCorners(detections, file.board, &tags_used);
    // In the board's order, whatever order the tags were detected in: frame to frame comparable.
    std::sort(corners.begin(), corners.end(), [](const BoardCorner& a, const BoardCorner& b) {
      return std::make_pair(a.first.y(), a.first.x()) < std::make_pair(b.first.y(), b.first.x());
    });
    std::vector<Eigen::Vector2d> pixels;
    for (const BoardCorner& c : corners) pixels.push_back(c.second);
    const bool whole = tags_used == board_tags;
    const bool still = whole && BoardStill(previous_px, pixels, kStillPx);
    previous_px = whole ? pixels : std::vector<Eigen::Vector2d>{};
    if (!still) continue;
    const BoardPose pose = EstimateBoardPose(detections, file.board, K);
    if (!pose.valid) continue;
    CoverageSample observed;
    observed.pixels = pixels;
    BoardTilt(pose.cMt, &observed.tilt_x_deg, &observed.tilt_y_deg);
    const SampleCoverage added = CoverSample(observed, K.width, K.height, coverage_config);
    if (!AddsToCoverage(coverage, added)) continue;
    AddToCoverage(added, &coverage);
    View v;
    v.image = fmt::format("views/{:03d}.png", file.views.size());
    WriteColorPng(frame.color, (fs::path(options.out_dir) / v.image).string());
    v.tags_used = tags_used;
    v.accepted = true;
    v.corners = std::move(corners);
    file.views.push_back(std::move(v));
    WriteViewsYaml(options.out_dir, file);  // nothing is lost on a stop
    out << fmt::format("sample {:2d}: tilt x {:+5.1f} y {:+5.1f} deg; {}\n", file.views.size(),
                       observed.tilt_x_deg, observed.tilt_y_deg,
                       CoverageFeedback(coverage, coverage_config));
    if (coverage.Complete() && static_cast<int>(file.views.size()) >= options.poses)
      stopped_by = "complete coverage";
  }
  out << fmt::format("sampling stopped ({}): {} samples; {}\n", stopped_by, file.views.size(),
                     CoverageFeedback(coverage, coverage_config));
  SolveAndReport(options.out_dir, &file, out);
}

TagBoardConfig IntrinsicsBoard() {
  TagBoardConfig board;
  board.rows = 4;
  board.cols = 5;
  board.tag_size_m = 0.030;
  board.spacing_m = 0.008;
  board.margin_m = 0.010;
  return board;
}

bool IsIntrinsicsFolder(const std::string& folder) { return fs::exists(ViewsPath(folder)); }

void ResolveIntrinsics(const std::string& folder, std::ostream& out) {
  ViewsFile file = ReadViewsYaml(folder);
  // Views rejected by the last solve's outlier test get another chance.
  for (View& v : file.views) {
    if (!v.accepted && v.reject_reason.rfind("reprojection error", 0) == 0) {
      v.accepted = true;
      v.reject_reason.clear();
    }
  }
  SolveAndReport(folder, &file, out);
}

void RunCalibrateIntrinsics(const CalibrateCommandOptions& options, std::ostream& out,
                            std::ostream& progress) {
  if (!options.hardware_path.empty()) {
    const std::unique_ptr<IntrinsicsHardware> hw =
        OpenIntrinsicsHardware(options.hardware_path, options.world_config, options.seed, out);
    RunHandHeldIntrinsics(options, *hw, std::cin, out);
    return;
  }
  if (options.out_dir.empty()) throw ConfigError("--out: an output folder is required");
  CheckRange("command line", "--poses", options.poses, kMinViews, 100, "");
  const CalibrationHardware hw =
      OpenCalibrationHardware(options.hardware_path, options.world_config, options.seed);
  World& world = *hw.devices->world();
  RgbdCamera& camera = hw.devices->camera();
  ViewsFile file;
  file.board = IntrinsicsBoard();
  file.factory = camera.intrinsics();
  file.simulated = true;  // without a hardware file every device is simulated
  file.camera_name = hw.devices->platform().config().camera_name;
  const std::vector<Eigen::Isometry3d> views =
      PlanBoardViews(file.factory, file.board, options.poses, options.seed);
  if (views.empty())
    throw std::runtime_error("no board pose in front of the camera keeps the whole board in view");
  out << fmt::format(
      "planned {} views of a {} x {} board of {:.0f} mm tags (of {} requested); devices: {}\n",
      views.size(), file.board.rows, file.board.cols, 1e3 * file.board.tag_size_m, options.poses,
      hw.config.source);
  const std::size_t board_index =
      world.AttachToCamera(MakeBoardRenderMesh(file.board, 4000.0), views.front());
  fs::create_directories(fs::path(options.out_dir) / "views");
  TagDetector detector(file.board.family);
  const int board_tags = file.board.rows * file.board.cols;
  Progress bar(progress, "intrinsics", static_cast<std::int64_t>(views.size()), "views");
  for (const Eigen::Isometry3d& cMt : views) {
    world.MoveAttachment(board_index, cMt);
    hw.devices->StepSimulation(kViewStep_s);
    RgbdFrame frame;
    camera.Grab(&frame);
    View v;
    v.image = fmt::format("views/{:03d}.png", file.views.size());
    WriteColorPng(frame.color, (fs::path(options.out_dir) / v.image).string());
    v.corners = MatchBoardCorners(detector.Detect(frame.color), file.board, &v.tags_used);
    if (v.tags_used == 0) {
      v.reject_reason = "board not seen";
    } else if (v.tags_used < kMinBoardFraction * board_tags) {
      v.reject_reason = fmt::format("board partly seen ({} of {} tags)", v.tags_used, board_tags);
    }
    v.accepted = v.reject_reason.empty();
    file.views.push_back(std::move(v));
    WriteViewsYaml(options.out_dir, file);  // nothing is lost on an error
    bar.Update(static_cast<std::int64_t>(file.views.size()));
  }
  bar.Finish();
  SolveAndReport(options.out_dir, &file, out);
}

}  // namespace aerograsp
