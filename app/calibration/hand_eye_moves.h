// The hand-eye wizard's steps on the devices: fault checks, checked moves
// at the rig's speed with a settle check, waiting for a hand-guided arm to be
// still, and taking a sample where the arm stands.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "app/calibration/calibration_hardware.h"
#include "app/calibration/hand_eye_samples.h"
#include "calib/tag_board.h"
#include "core/camera_model.h"
#include "core/platform.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

class PlatformCollision;

/// A reason to stop the run at once: the arms are stopped where they are and
/// the samples kept.
struct StopRun {
  std::string reason;
};

/// Control period of the wizard's moves, s.
constexpr double kStep_s = 0.05;

/// Throws StopRun on Ctrl-C, an outside emergency stop
/// (HandEyeHardware::SetEmergencyStop: ROS 2's) or when a servo stopped
/// answering or left its voltage or temperature range.
void CheckFaults(HandEyeHardware& hw);
/// Why the straight joint-space move from `from` to `to` is refused ("" when
/// every configuration along it keeps clear of the safe volume and of the
/// other arm where it stands).
std::string CheckMove(const PlatformCollision& collision, Side side, const Eigen::VectorXd& from,
                      const Eigen::VectorXd& to, const Eigen::VectorXd& other_q);
/// Moves `side` to `target` at the rig's joint speed (targets sent every
/// control period along the straight joint-space line), then waits until it
/// settles. Returns "" when settled, else why not.
std::string MoveAndSettle(HandEyeHardware& hw, Side side, const Eigen::VectorXd& target);
/// The board seen from where the arm stands now: its pose, or why not.
std::string BoardSeen(const RgbdFrame& frame, const CalibrationRig& rig, const CameraIntrinsics& K,
                      TagDetector* detector);
/// Joint angles in degrees, "a, b, c" with one decimal.
std::string Degrees(const Eigen::VectorXd& q);
/// Hand-guided: waits until a person has let go of the limp arm (readings
/// unchanged for the settle window) while the driver's command follows the
/// readings, so that the arm does not jump when its torque comes back.
/// Returns "" when still, else why the sample is rejected.
std::string WaitStill(HandEyeHardware& hw, Side side);
/// One sample where the arm stands: the joints read, a frame grabbed, the
/// board detected and the rejection rules applied (`unsettled`, when not
/// empty, rejects it); the image and, accepted, its ViSP files written.
WizardSample TakeSample(HandEyeHardware& hw, Side side, TagDetector* detector,
                        const std::string& out_dir, std::size_t index, const std::string& unsettled,
                        RgbdFrame* frame);
/// The accepted samples' spread and, when it is short, what to add.
std::string DiversityLine(const std::vector<WizardSample>& samples);

}  // namespace aerograsp
