// `aerograsp bench [--hardware CONFIG] --out DIR`: perception and servoing
// measured against AprilTags on a test stand. The vehicle stands fixed (in the
// simulator: no sway, no drift); the object carries a tag board at a known
// place oMt and is moved by a script through the camera's view, within the
// arms' reach part of the time. Per camera frame the board's pose gives an
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

namespace aerograsp {

struct BenchCommandOptions {
  std::string out_dir;        ///< created; the report
  std::string hardware_path;  ///< hardware YAML; empty: every device simulated in-process
  std::string
      world_config;        ///< world YAML without --hardware; empty: data/config/world_default.yaml
  std::string object;      ///< shipped object name or model path; empty: the world's
  int frames = 300;        ///< camera frames, [1, 100000]
  std::uint64_t seed = 1;  ///< world seed
  /// The arms servo to the planned grasp moved back this far along its
  /// approach axis (a hover point: nothing is grasped); 0 = the grasp itself. [0, 0.3] m.
  double hover_m = 0.04;
  double path_period_s = 10.0;  ///< the scripted path repeats with this period, [1, 1000] s
  /// Scale of the scripted path's amplitudes (1: +-6 cm fore and aft, +-2 cm
  /// sideways and vertically, +-0.1 rad of yaw); 0 holds the object still at
  /// the mission's grasp point. [0, 3]
  double path_scale = 1.0;
  /// The board (frame t) on the object (frame o); empty: centred on the top of
  /// the object, printed face up (for the crawler: in the recess between its tracks).
  std::optional<Eigen::Isometry3d> oMt;
  /// Perception YAML (detection/perception_config.h); empty: the one the mission config names.
  std::string perception_config;
  /// The mission YAML whose planner, servo, grasp-sequence and policy settings
  /// the bench uses (app/runtime/mission_config.h); empty: data/config/mission_default.yaml.
  std::string mission_config;
  TelemetryOptions telemetry;
};

/// @throws ConfigError for bad options, a bad perception YAML or a hardware config the bench cannot
/// run with (it needs the simulated camera to move the object by script);
/// std::runtime_error when the board was never seen or the object never found
/// (the report and summary.json are written first), or DIR cannot be written.
void RunBenchCommand(const BenchCommandOptions& options, std::ostream& out, std::ostream& progress);

}  // namespace aerograsp
