// `aerograsp replay RECORDING --out DIR`: runs the perception pipeline frame by
// frame on a recording (a sequence folder, a RealSense .bag, a TUM RGB-D folder:
// hardware/bag/recording.h) and writes
//   DIR/poses.csv      frame, stamp_s, cMo (t in m, q as w x y z), confidence, state, ...
//   DIR/summary.json   frames, timings per stage, and accuracy against the
//                      ground truth when the sequence has it
//   DIR/pose_vs_truth.png  estimate vs truth per axis over time (paper Fig. 12)
//   DIR/index.html     the headline figures and the estimates over time as
//                      interactive charts (app/report/replay_report.h)
//   DIR/replay.mcap    the telemetry (app/commands/telemetry_options.h), unless
//                      off: the frames, the estimate and the truth as transforms
// Beside ours it runs ViSP's model-based tracker with dense depth features
// (vpMbGenericTracker), initialised the same way, and reports it the same way.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/commands/telemetry_options.h"
#include "hardware/bag/recording.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct ReplayCommandOptions {
  std::string sequence;      ///< sequence folder, .bag file or TUM RGB-D folder
  std::string out_dir;       ///< poses.csv, summary.json, index.html, pose_vs_truth.png
  bool overwrite = false;    ///< replace a report already in out_dir
  std::string object;        ///< overrides the sequence's object (shipped name or model path)
  std::string detector;      ///< ONNX path; "" = data/objects/NAME/detector.onnx when it exists
  bool use_detector = true;  ///< false: whole-frame global registration, no CNN
  std::optional<Eigen::Isometry3d> init_cMo;  ///< known first pose
  bool init_from_truth = false;  ///< take the first frame's ground truth as the known first pose
  bool run_peer = true;          ///< also run ViSP's vpMbGenericTracker (dense depth)
  int max_frames = 0;            ///< 0 = all
  /// "camera": the pose filter runs in the camera frame (the recording needs
  /// nothing else); "world": in the world, with each frame's camera pose from
  /// the recorded vehicle state (vehicle.csv) and the camera mount of `platform`.
  std::string filter_frame = "camera";
  std::string platform;  ///< platform YAML for the camera mount; "" = config/platform_4dof.yaml
  /// Perception YAML (detection/perception_config.h); "" = the code's defaults.
  /// With filter_frame "world", weak_direction_std_m is 0.02 m unless the file sets it.
  std::string perception_config;
  /// TUM folders: intrinsics file, the object in groundtruth.txt's world (gives
  /// the ground truth); .bag and TUM: the colour-depth pairing gap (0: one depth period).
  RecordingOptions recording;
  TelemetryOptions telemetry;
};

/// Reads "x y z qw qx qy qz" (metres, unit quaternion w first) as cMo.
/// @throws std::invalid_argument for a wrong count, non-numbers or a zero quaternion.
Eigen::Isometry3d ParsePose(const std::string& text);
/// The same from the seven numbers; messages name `option`.
Eigen::Isometry3d PoseFromValues(const std::vector<double>& xyz_qwxyz,
                                 const std::string& option = "--init-pose");

/// @throws HardwareError / ConfigError / MeshError naming the file (missing or
/// truncated sequence, unknown object, corrupt detector model, bad perception
/// YAML: checked first), std::runtime_error
/// when DIR cannot be written. Returns kExitOk (app/exit_codes.h), or
/// kExitStoppedEarly when a frame could not be read: the report then holds the
/// frames before it and says why it stopped ("stopped_early").
int RunReplayCommand(const ReplayCommandOptions& options, std::ostream& out,
                     std::ostream& progress);

/// Adds `replay`'s options to `cmd` (a CLI11 subcommand), with the recording
/// options (AddRecordingOptions); the poses reach `options` when the command
/// line has been parsed.
void AddReplayOptions(CLI::App* cmd, ReplayCommandOptions* options);

}  // namespace aerograsp
