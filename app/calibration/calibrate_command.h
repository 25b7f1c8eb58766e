// `aerograsp calibrate`: the camera-to-arm-base transform of one arm from an
// AprilTag board on its gripper (eye-to-hand), in the simulator or through
// `--hardware CONFIG`; `--intrinsics` for the camera's intrinsics; and
// `--resolve DIR` to solve again from saved samples.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

#include "app/commands/telemetry_options.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct CalibrateCommandOptions {
  std::string arm{"left"};  ///< "left" | "right"
  /// the camera's intrinsics instead of an arm (app/calibration/calibrate_intrinsics.h)
  bool intrinsics = false;
  std::string out_dir;     ///< samples, calibration YAML, summary.json
  bool overwrite = false;  ///< replace a report already in out_dir
  /// when set: solve again from the samples (or views) saved there, ours (samples.yaml) or in
  /// ViSP's convention (pose_rPe_N.yaml ...)
  std::string resolve_dir;
  std::string setup{"eye-to-hand"};  ///< of a ViSP data set: "eye-to-hand" | "eye-in-hand"
  double tag_size_m = 0.0;   ///< of a ViSP data set without pose_cPo files: the tag's edge, m
  std::string world_config;  ///< default data/config/world_default.yaml
  /// empty: the built-in simulation (app/calibration/calibration_hardware.h)
  std::string hardware_path;
  int poses = 15;              ///< arm poses (or board views) to visit, [4, 100]
  std::uint64_t seed = 1;      ///< world and pose-planning seed
  bool dry_run = false;        ///< pre-flight check and plan only: nothing moves
  bool yes = false;            ///< no confirmation asked before the arm moves (scripts)
  bool hand_guided = false;    ///< the arm's torque off: a person places it, Enter takes a sample
  TelemetryOptions telemetry;  ///< the hand-eye wizard's telemetry (DIR/calibrate.mcap)
};

class HandEyeHardware;

/// The report is written as a transaction (app/report/report_folder.h): an
/// earlier report in `out_dir` is refused unless `overwrite`; a run that fails
/// before a sample or view was taken leaves an earlier report as it was; one
/// stopped after (Ctrl-C, a device fault, no usable samples) commits what it
/// took with a summary.json saying why it stopped (`stopped_early`, `error`)
/// and throws; a dry run's report is the board, the plan and a summary.json
/// (`dry_run`). `--resolve DIR` solves again in DIR itself.
/// With `intrinsics`, runs RunCalibrateIntrinsics (app/calibration/calibrate_intrinsics.h);
/// `--resolve` picks the kind from what DIR holds (our samples.yaml, intrinsics
/// views, or a data set in ViSP's convention, app/calibration/calibration_visp.h).
/// Otherwise the hand-eye wizard on the devices of `hardware_path`
/// (app/calibration/calibration_hardware.h): opens the arms and the camera, runs the
/// pre-flight check (servos, voltages, temperatures, joint limits, camera,
/// board seen from the start pose), plans diverse arm poses that show the
/// board to the camera and keep clear of the safe volume and of the other arm,
/// shows them (table, DIR/plan.png) and, unless `dry_run`, asks for a
/// confirmation on `in` when a hardware file names the devices (`yes` skips
/// it; the in-process simulator is not asked), then visits them at the rig's
/// reduced speed (each move checked before it is sent, a settle check from the
/// joint readings), detects the board at each, rejects bad samples, solves
/// (ViSP, OpenCV's five methods, corner refinement), and writes DIR/samples/,
/// DIR/samples.yaml, DIR/visp/ (ViSP's convention), DIR/calibration_<arm>.yaml,
/// .urdf and _tf.sh, DIR/summary.json and DIR/poses.png.
/// Ctrl-C or a fault (a servo that stops answering or leaves its voltage or
/// temperature range, the camera stopping) stops both arms where they are and
/// throws HardwareError; the samples taken so far are kept on disk.
/// @throws std::runtime_error / ConfigError / HardwareError with a message naming
/// what is wrong (a device that does not open, with its port; a failed
/// pre-flight check; no board visible; all samples rejected; a singular pose set).
void RunCalibrateCommand(const CalibrateCommandOptions& options, std::istream& in,
                         std::ostream& out, std::ostream& progress);
/// The hand-eye wizard on devices already opened by OpenHandEyeHardware
/// (app/calibration/calibration_hardware.h): what RunCalibrateCommand runs after opening
/// them. With `hand_guided`, the arm's joints go limp after the confirmation;
/// each line read from `in` takes a sample where the person left the arm
/// (joints read from the bus once they are still, a frame from the camera,
/// the same rejection rules), prints the set's diversity and what to add
/// ("rotate the gripper more about its approach axis (z)") and suggests the
/// next planned pose; `q` or the end of `in` solves, with the torque back on
/// where the arm stands.
void RunHandEyeWizard(const CalibrateCommandOptions& options, HandEyeHardware& hw, std::istream& in,
                      std::ostream& out, std::ostream& progress);
/// The same, with the confirmation read from std::cin.
void RunCalibrateCommand(const CalibrateCommandOptions& options, std::ostream& out,
                         std::ostream& progress);

/// Adds `calibrate`'s options to `cmd` (a CLI11 subcommand).
void AddCalibrateOptions(CLI::App* cmd, CalibrateCommandOptions* options);

}  // namespace aerograsp
