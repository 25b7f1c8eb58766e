#include "app/calibration/hand_eye_moves.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/calibration/calibration_samples.h"
#include "app/calibration/calibration_visp.h"
#include "app/calibration/interrupt_guard.h"
#include "core/collision.h"
#include "hardware/device_health.h"
#include "hardware/scs/scs_arms_driver.h"
#include "telemetry/telemetry.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kMaxReprojectionPx = 1.0;  // a sample above this is rejected
constexpr double kMinBoardFraction = 0.5;   // of the board's tags seen
constexpr double kPathCheckRad = 0.02;      // spacing of the configurations checked along a move

}  // namespace

void CheckFaults(HandEyeHardware& hw) {
  if (InterruptGuard::Interrupted()) throw StopRun{"interrupted (Ctrl-C)"};
  const std::string stop = hw.PollEmergencyStop();
  if (!stop.empty()) throw StopRun{stop};
  ScsArmsDriver* scs = hw.scs();
  if (!scs) return;
  // The mission's servo checks (hardware/device_health.h) with the rig's bounds.
  const CalibrationRig& rig = hw.rig();
  DeviceHealthLimits limits;
  limits.servo_max_failed_reads = rig.max_failed_reads;
  limits.servo_min_voltage_v = rig.min_voltage_v;
  limits.servo_max_voltage_v = rig.max_voltage_v;
  limits.servo_max_temperature_c = rig.max_temperature_c;
  for (const ScsServoStatus& s : scs->servo_statuses()) {
    for (const DeviceFault& f : CheckServo(s, /*reading_age_s=*/0.0, limits)) {
      if (f.kind != DeviceFaultKind::kServoSilent) throw StopRun{f.Text()};
      throw StopRun{fmt::format("{} stopped answering on {} ({} reads failed in a row)", f.device,
                                hw.ArmsWhere(), s.failed_reads)};
    }
  }
}

std::string CheckMove(const PlatformCollision& collision, Side side, const Eigen::VectorXd& from,
                      const Eigen::VectorXd& to, const Eigen::VectorXd& other_q) {
  const int steps =
      std::max(1, static_cast<int>(std::ceil((to - from).cwiseAbs().maxCoeff() / kPathCheckRad)));
  for (int k = 1; k <= steps; ++k) {
    const Eigen::VectorXd q = from + (to - from) * (static_cast<double>(k) / steps);
    if (collision.ArmInSafeVolume(side, q)) return "the move would enter the safe volume";
    if (side == Side::kLeft ? collision.ArmsCollide(q, other_q, 0.01)
                            : collision.ArmsCollide(other_q, q, 0.01))
      return "the move would come within 1 cm of the other arm";
  }
  return "";
}

std::string MoveAndSettle(HandEyeHardware& hw, Side side, const Eigen::VectorXd& target) {
  const CalibrationRig& rig = hw.rig();
  ArmsDriver& arms = hw.arms();
  const Eigen::VectorXd start = arms.JointPositions(side);
  const double duration =
      (target - start).cwiseAbs().maxCoeff() / (rig.joint_speed_deg_s * M_PI / 180.0);
  const double t0 = hw.now_s();
  for (double f = 0.0; f < 1.0;) {
    f = duration > 0.0 ? std::min(1.0, (hw.now_s() - t0 + kStep_s) / duration) : 1.0;
    arms.SetJointTargets(side, start + f * (target - start));
    hw.Wait(kStep_s);
    CheckFaults(hw);
  }
  // Settled: every joint within the tolerance of its target, readings unchanged
  // (by less than half the tolerance) for the settle window. The target is sent
  // every period, as a control loop does (the bus driver's watchdog holds stale ones).
  const double tolerance = rig.settle_tolerance_deg * M_PI / 180.0;
  const double t_settle = hw.now_s();
  Eigen::VectorXd last = arms.JointPositions(side);
  double still_since = hw.now_s();
  while (hw.now_s() - t_settle < rig.settle_timeout_s) {
    arms.SetJointTargets(side, target);
    hw.Wait(kStep_s);
    CheckFaults(hw);
    const Eigen::VectorXd q = arms.JointPositions(side);
    if ((q - last).cwiseAbs().maxCoeff() > 0.5 * tolerance) still_since = hw.now_s();
    last = q;
    if ((q - target).cwiseAbs().maxCoeff() <= tolerance &&
        hw.now_s() - still_since >= rig.settle_window_s - 1e-9)
      return "";
  }
  return fmt::format("arm not settled after {:.1f} s", rig.settle_timeout_s);
}

std::string BoardSeen(const RgbdFrame& frame, const CalibrationRig& rig, const CameraIntrinsics& K,
                      TagDetector* detector) {
  if (frame.color.width == 0) return "no frame";
  const BoardPose pose = EstimateBoardPose(detector->Detect(frame.color), rig.board, K);
  if (!pose.valid)
    return fmt::format(
        "not seen (no tag of the {}x{} board, ids {}-{}): is it on the gripper, "
        "facing the camera?",
        rig.board.rows, rig.board.cols, rig.board.first_id,
        rig.board.first_id + rig.board.rows * rig.board.cols - 1);
  return "";
}

std::string Degrees(const Eigen::VectorXd& q) {
  std::string s;
  for (int j = 0; j < q.size(); ++j) s += fmt::format("{}{:.1f}", j ? ", " : "", q[j] * kRadToDeg);
  return s;
}

std::string WaitStill(HandEyeHardware& hw, Side side) {
  const CalibrationRig& rig = hw.rig();
  ArmsDriver& arms = hw.arms();
  const double tolerance = rig.settle_tolerance_deg * M_PI / 180.0;
  const double t0 = hw.now_s();
  Eigen::VectorXd last = arms.JointPositions(side);
  double still_since = t0;
  while (hw.now_s() - t0 < rig.settle_timeout_s) {
    arms.SetJointTargets(side, arms.JointPositions(side));
    hw.Wait(kStep_s);
    CheckFaults(hw);
    const Eigen::VectorXd q = arms.JointPositions(side);
    if ((q - last).cwiseAbs().maxCoeff() > 0.5 * tolerance) still_since = hw.now_s();
    last = q;
    if (hw.now_s() - still_since >= rig.settle_window_s - 1e-9) return "";
  }
  return fmt::format("arm still moving after {:.1f} s", rig.settle_timeout_s);
}

WizardSample TakeSample(HandEyeHardware& hw, Side side, TagDetector* detector,
                        const std::string& out_dir, std::size_t index, const std::string& unsettled,
                        RgbdFrame* frame) {
  const TagBoardConfig& board = hw.rig().board;
  RgbdCamera& camera = hw.camera();
  if (!camera.Grab(frame)) throw StopRun{"camera: no frame: the stream stopped"};
  WizardSample s;
  s.image = fmt::format("samples/{:03d}.png", index);
  s.q_rad = hw.arms().JointPositions(side);
  s.data.bMe = hw.platform().arm(side).ForwardKinematics(s.q_rad);
  WriteColorPng(frame->color, (fs::path(out_dir) / s.image).string());
  const std::vector<TagDetection> detections = detector->Detect(frame->color);
  const BoardPose pose = EstimateBoardPose(detections, board, camera.intrinsics());
  s.data.cMt = pose.cMt;
  s.data.corners = MatchBoardCorners(detections, board);
  const int board_tags = board.rows * board.cols;
  if (!unsettled.empty()) {
    s.reject_reason = unsettled;
  } else if (!pose.valid || pose.tags_used < kMinBoardFraction * board_tags) {
    s.reject_reason = fmt::format("board partly seen ({} of {} tags)", pose.tags_used, board_tags);
  } else if (pose.reprojection_rms_px > kMaxReprojectionPx) {
    s.reject_reason = fmt::format("reprojection error {:.2f} px", pose.reprojection_rms_px);
  }
  s.accepted = s.reject_reason.empty();
  if (TelemetrySink* sink = hw.telemetry()) {
    TelemetryImage image;
    image.t_s = hw.now_s();
    image.K = camera.intrinsics();
    image.color = &frame->color;
    if (!frame->depth.empty()) image.depth = &frame->depth;
    image.depth_scale_m = camera.depth_scale_m();
    sink->Image(image);
    if (pose.valid)
      sink->Transforms(image.t_s,
                       {{telemetry_frame::kCamera, telemetry_frame::kTagBoard, pose.cMt}});
    sink->Log(image.t_s, s.accepted ? TelemetryLevel::kInfo : TelemetryLevel::kWarn, "calibrate",
              fmt::format("sample {}: {}", index,
                          s.accepted ? "accepted" : "rejected: " + s.reject_reason));
  }
  if (s.accepted) {  // the same sample in ViSP's convention (eye-to-hand: rPe = bMe, cPo = cMt)
    WriteVispSample((fs::path(out_dir) / "visp").string(), static_cast<int>(index) + 1, s.data.bMe,
                    s.data.cMt, (fs::path(out_dir) / s.image).string());
  }
  return s;
}

std::string DiversityLine(const std::vector<WizardSample>& samples) {
  std::vector<HandEyeSample> used;
  for (const WizardSample& s : samples) {
    if (s.accepted) used.push_back(s.data);
  }
  const PoseSetDiversity d = MeasureDiversity(used);
  const std::string advice = DiversityAdvice(d, used.size());
  return fmt::format("{} accepted, {:.0f} deg apart at most, rotation axes span {} dimension(s){}",
                     used.size(), d.max_rotation_deg, d.axis_rank,
                     advice.empty() ? "" : ": " + advice);
}

}  // namespace aerograsp
