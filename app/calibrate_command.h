// `aerograsp calibrate`: the camera-to-arm-base transform of one arm from an
// AprilTag board on its gripper (eye-to-hand), in the simulator or through
// `--hardware CONFIG`; `--intrinsics` for the camera's intrinsics; and
// `--resolve DIR` to solve again from saved samples.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace aerograsp {

struct CalibrateCommandOptions {
  std::string arm{"left"};  ///< "left" | "right"
  bool intrinsics =
      false;            ///< the camera's intrinsics instead of an arm (app/calibrate_intrinsics.h)
  std::string out_dir;  ///< samples, calibration YAML, summary.json
  std::string resolve_dir;        ///< when set: solve again from the samples (or views) saved there
  std::string world_config;       ///< default data/config/world_default.yaml
  std::string hardware_path;      ///< empty: the built-in simulation (app/calibration_hardware.h)
  int poses = 15;                 ///< arm poses (or board views) to visit, [4, 100]
  std::uint64_t seed = 1;         ///< world and pose-planning seed
  double settle_timeout_s = 3.0;  ///< longest wait for the arm to settle at a pose
};

/// With `intrinsics`, runs RunCalibrateIntrinsics (app/calibrate_intrinsics.h);
/// `--resolve` picks the kind from what DIR holds. Otherwise:
/// plans diverse arm poses that show the board to the camera and keep clear
/// of the safe volume, visits them in the simulator, detects the board at
/// each, rejects bad samples, solves (ViSP, OpenCV's five methods, corner
/// refinement), and writes DIR/samples/, DIR/calibration_<arm>.yaml,
/// DIR/summary.json and DIR/poses.png.
/// @throws std::runtime_error / ConfigError with a message naming what is wrong
/// (no board visible, all samples rejected, a singular pose set); the samples
/// collected so far are kept on disk.
void RunCalibrateCommand(const CalibrateCommandOptions& options, std::ostream& out,
                         std::ostream& progress);

}  // namespace aerograsp
