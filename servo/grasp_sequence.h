// The grasp of one arm as a small phase machine on top of ArmServo (paper,
// Sect. 4.2 and Fig. 7b): move to the pre-catch pose (back from the grasp along
// its approach axis), then to the grasp pose, then close the gripper. Each
// phase has a convergence threshold and a timeout. Pure algorithm: it returns
// joint commands and a gripper command; no threads, files or devices.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "core/platform.h"
#include "servo/arm_servo.h"
#include "servo/ik.h"

namespace aerograsp {

struct GraspSequenceConfig {
  double precatch_distance_m{0.08};  ///< pre-catch pose: back along the grasp's z, (0, 0.5] m
  PoseTolerance precatch_tolerance{0.005, 0.05, 0.1};  ///< pre-catch counts as reached
  PoseTolerance grasp_tolerance{0.002, 0.02, 0.05};    ///< grasp pose counts as reached
  double precatch_timeout_s{6.0};                      ///< to reach the pre-catch pose, (0, 600] s
  double grasp_timeout_s{3.0};  ///< from the pre-catch to the grasp pose, (0, 600] s
  double close_time_s{0.8};     ///< gripper closing (PlatformConfig gripper), (0, 10] s

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

enum class GraspPhase {
  kPreCatch,  ///< servoing to the pre-catch pose, gripper open
  kGrasp,     ///< servoing to the grasp pose, gripper open
  kClose,     ///< at the grasp pose, gripper closing
  kDone,      ///< gripper closed: holding
  kTimedOut,  ///< a phase ran out of time: holding, gripper open
};
const char* GraspPhaseName(GraspPhase phase);

struct GraspCommand {
  ServoCommand joints;  ///< the arm's command (zero dq on hold)
  ServoStatus servo_status = ServoStatus::kNoTarget;
  GripperCommand gripper = GripperCommand::kOpen;
  GraspPhase phase = GraspPhase::kPreCatch;  ///< after this step
  double phase_time_s = 0.0;                 ///< time spent in `phase` so far
};

class GraspSequence {
 public:
  /// `servo` must outlive the sequence; the sequence sets its targets.
  /// @throws ConfigError when config is invalid.
  GraspSequence(ArmServo* servo, const GraspSequenceConfig& config);

  /// Starts (again) at the pre-catch phase at time now_s, gripper open.
  void Start(double now_s);
  /// The grasp pose bMg (in the arm base) observed at stamp_s. `is_switch`
  /// marks another grasp: in the grasp or close phase the sequence then goes
  /// back to the pre-catch pose of the new grasp and opens the gripper.
  void SetGrasp(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch = false);
  /// The same with the pre-catch pose given (e.g. the planner's, which a 4-DoF
  /// arm reaches: moving straight back along a grasp's approach axis turns that
  /// axis, so PreCatchPose(bMg) itself may be out of its reach).
  void SetGrasp(const Eigen::Isometry3d& bMg, const Eigen::Isometry3d& bMp, double stamp_s,
                bool is_switch = false);

  /// One cycle: servo toward the phase's pose, advance the phase. Never throws.
  /// A servo hold (stale or invalid target, unreachable, safe volume) holds the
  /// arm but the phase clock runs on, so a lasting fault ends in kTimedOut.
  GraspPhase Step(const Eigen::VectorXd& q, double now_s, double dt_s, GraspCommand* out);

  GraspPhase phase() const { return phase_; }
  /// The gripper reports that it holds the object: a close in progress ends
  /// here (kDone) and the arm keeps still from now on. The object moves with a
  /// gripper that holds it, so servoing on towards a target taken from the
  /// object's estimate would only drag the object (and the estimate) along.
  void GripperHolds(double now_s);
  /// While false the grasp pose does not count as reached (the arm servoes
  /// on but does not close, its phase clock running): the caller says whether
  /// the target still lies on the object. True by default and after Start.
  void SetTargetOnObject(bool on_object) { target_on_object_ = on_object; }
  bool target_on_object() const { return target_on_object_; }
  /// While `hold` is set the sequence stays at the pre-catch pose once it is
  /// reached (tracking it, its phase clock paused) instead of moving in: the
  /// two arms go in together (paper Fig. 7b, "approaching pose").
  void HoldAtPreCatch(bool hold) { hold_at_precatch_ = hold; }
  /// True while in the pre-catch phase with the pre-catch pose met.
  bool at_precatch() const { return at_precatch_; }
  /// While `hold` is set the sequence stays at the grasp pose once it is
  /// reached (tracking it, its phase clock running) instead of closing: the
  /// caller closes the two grippers one right after the other.
  void HoldAtGrasp(bool hold) { hold_at_grasp_ = hold; }
  /// True while in the grasp phase with the grasp pose met.
  bool at_grasp() const { return at_grasp_; }
  /// The pre-catch pose for a grasp: bMg moved back precatch_distance_m along z_g.
  Eigen::Isometry3d PreCatchPose(const Eigen::Isometry3d& bMg) const;

 private:
  void Enter(GraspPhase phase, double now_s);

  ArmServo* servo_;
  GraspSequenceConfig config_;
  GraspPhase phase_ = GraspPhase::kPreCatch;
  double phase_start_s_ = 0.0;
  bool has_grasp_ = false;
  Eigen::Isometry3d bMg_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d bMp_ = Eigen::Isometry3d::Identity();  // the pre-catch pose
  double grasp_stamp_s_ = 0.0;
  bool switch_pending_ = false;  // passed to the servo with the next target
  bool hold_at_precatch_ = false;
  bool at_precatch_ = false;
  bool hold_at_grasp_ = false;
  bool at_grasp_ = false;
  bool target_on_object_ = true;
};

}  // namespace aerograsp
