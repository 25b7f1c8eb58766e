#include "app/calibration/calibrate_intrinsics.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_samples.h"
#include "app/calibration/intrinsics_views.h"
#include "app/calibration/tag_board_mesh.h"
#include "app/report/progress.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kMinBoardFraction = 0.5;  // of the board's tags seen
constexpr double kViewStep_s = 0.1;  // simulated time between views (the hand moves the board)

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

}  // namespace

TagBoardConfig IntrinsicsBoard() {
  TagBoardConfig board;
  board.rows = 4;
  board.cols = 5;
  board.tag_size_m = 0.030;
  board.spacing_m = 0.008;
  board.margin_m = 0.010;
  return board;
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
  CheckRange("command line", "--poses", options.poses, kMinIntrinsicsViews, 100, "");
  // Without a hardware file every device is simulated in-process.
  const std::string world_path =
      options.world_config.empty() ? DataPath("config/world_default.yaml") : options.world_config;
  const HardwareConfig config =
      HardwareConfig::InProcessSimulation(WorldConfig::Load(world_path).platform, world_path);
  const std::unique_ptr<Hardware> devices = Hardware::Open(config, options.seed);
  World& world = *devices->world();
  RgbdCamera& camera = devices->camera();
  ViewsFile file;
  file.board = IntrinsicsBoard();
  file.factory = camera.intrinsics();
  file.simulated = true;
  file.camera_name = devices->platform().config().camera_name;
  const std::vector<Eigen::Isometry3d> views =
      PlanBoardViews(file.factory, file.board, options.poses, options.seed);
  if (views.empty())
    throw std::runtime_error("no board pose in front of the camera keeps the whole board in view");
  out << fmt::format(
      "planned {} views of a {} x {} board of {:.0f} mm tags (of {} requested); devices: {}\n",
      views.size(), file.board.rows, file.board.cols, 1e3 * file.board.tag_size_m, options.poses,
      config.source);
  const std::size_t board_index =
      world.AttachToCamera(MakeBoardRenderMesh(file.board, 4000.0), views.front());
  fs::create_directories(fs::path(options.out_dir) / "views");
  TagDetector detector(file.board.family);
  const int board_tags = file.board.rows * file.board.cols;
  Progress bar(progress, "intrinsics", static_cast<std::int64_t>(views.size()), "views");
  for (const Eigen::Isometry3d& cMt : views) {
    world.MoveAttachment(board_index, cMt);
    devices->StepSimulation(kViewStep_s);
    RgbdFrame frame;
    camera.Grab(&frame);
    SavedView v;
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
  SolveIntrinsicsAndReport(options.out_dir, &file, out);
}

}  // namespace aerograsp
