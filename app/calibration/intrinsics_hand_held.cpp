#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "app/calibration/calibrate_intrinsics.h"
#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_samples.h"
#include "app/calibration/interrupt_guard.h"
#include "app/calibration/intrinsics_views.h"
#include "app/calibration/tag_board_mesh.h"
#include "core/transforms.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kHeldDistance_m = 0.45;  // simulated: the board's rest pose in front of the camera

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
  hw->rig_ = CalibrationRig::Load(hardware_path);
  const CalibrationRig& rig = hw->rig_;
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
  CheckRange("command line", "--poses", options.poses, kMinIntrinsicsViews, 100, "");
  const CoverageConfig& coverage_config = hw.rig().coverage;
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
      if (++missed < hw.rig().max_missed_frames) continue;
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
    const bool still = whole && BoardStill(previous_px, pixels, hw.rig().still_px);
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
    SavedView v;
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
  SolveIntrinsicsAndReport(options.out_dir, &file, out);
}

}  // namespace aerograsp
