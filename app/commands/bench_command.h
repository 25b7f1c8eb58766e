// `aerograsp bench [--hardware CONFIG] --out DIR`: perception and servoing
// measured against AprilTags on a test stand. The vehicle stands fixed (in the
// simulator: no sway, no drift); the object carries a tag board at a known
// place oMt. Without --hardware the in-process simulator moves the object by a
// script through the camera's view, within the arms' reach part of the time.
// With --hardware (the real camera and arms) a person moves the object by hand
// in front of the camera; the board and its place on the object are the
// hardware file's `bench` section (with a simulated camera its world carries
// the board there and moves the object as the world file says: the bench never
// places it). Per camera frame the board's pose gives an
// independent cMo (cMt * oMt^-1); the tracker (detection/object_tracker.h,
// the same as replay and mission) estimates cMo; the arms servo to the planned
// grasp, or to a hover point just off it, and the tool's tracking error is
// measured against that target. Writes
//   DIR/summary.json  frames, tag_frames, translation_rmse_m, rotation_rmse_deg
//                     (perception against the tags), servo_error_m_median, and
//                     in simulation the tags' and perception's error to the truth
//   DIR/frames.csv    one row per camera frame
//   DIR/index.html    with pose_vs_tags.png, servo_error.png, joints.png, camera.png
//   DIR/bench.mcap    the telemetry (app/commands/telemetry_options.h), unless off
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "app/commands/telemetry_options.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct BenchCommandOptions {
  std::string out_dir;        ///< the report (written aside, renamed at the end)
  bool overwrite = false;     ///< replace a report already in out_dir
  std::string hardware_path;  ///< hardware YAML; empty: every device simulated in-process
  /// World YAML (with --hardware it replaces the file's world); empty: the hardware
  /// file's, or data/config/world_default.yaml.
  std::string world_config;
  /// Shipped object name or model path; empty: the world's (the crawler without a world).
  std::string object;
  int frames = 300;        ///< camera frames, [1, 100000]
  std::uint64_t seed = 1;  ///< world seed
  /// The arms servo to the planned grasp moved back this far along its
  /// approach axis (a hover point: nothing is grasped); 0 = the grasp itself. [0, 0.3] m.
  double hover_m = 0.04;
  /// The scripted path (without --hardware) repeats with this period, [1, 1000] s.
  double path_period_s = 10.0;
  /// Scale of the scripted path's amplitudes (1: +-6 cm fore and aft, +-2 cm
  /// sideways and vertically, +-0.1 rad of yaw); 0 holds the object still at
  /// the mission's grasp point. [0, 3]
  double path_scale = 1.0;
  /// The board (frame t) on the object (frame o), without --hardware; empty: centred on
  /// the top of the object, printed face up (for the crawler: in the recess between its tracks).
  std::optional<Eigen::Isometry3d> oMt;
  /// Perception YAML (detection/perception_config.h); empty: the one the mission config names.
  std::string perception_config;
  /// The mission YAML whose planner, servo, grasp-sequence and policy settings
  /// the bench uses (app/runtime/mission_config.h); empty: data/config/mission_default.yaml.
  std::string mission_config;
  TelemetryOptions telemetry;
};

/// On the simulated camera the run is on the world's clock (deterministic);
/// on the real one on the steady clock, the drivers' threads running.
/// Ctrl-C stops the arms where they are, writes the report of the frames so
/// far and throws HardwareError.
/// @throws ConfigError for bad options, a bad perception or hardware YAML, a
/// mix of devices the bench cannot run with (CheckBenchHardware), or
/// --board-pose with --hardware; HardwareError for a device that does not open
/// or a camera stream that ends; std::runtime_error when the board was never
/// seen or the object never found (the report and summary.json are written
/// first), or DIR cannot be written.
void RunBenchCommand(const BenchCommandOptions& options, std::ostream& out, std::ostream& progress);

/// Adds `bench`'s options to `cmd` (a CLI11 subcommand); the board's pose
/// reaches `options` when the command line has been parsed.
void AddBenchOptions(CLI::App* cmd, BenchCommandOptions* options);

}  // namespace aerograsp
