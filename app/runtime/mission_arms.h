// The two arms following the mission's dual grasp: per arm a servo and a grasp
// sequence (pre-catch, in, close), the followed pair solved again every cycle
// where the object is now (kept only on the IK branch it was followed on, the
// policy's gate), and the way home after a failed attempt.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "app/runtime/mission_config.h"
#include "core/arm_ik.h"
#include "grasp/planner.h"
#include "hardware/arms_driver.h"
#include "mission/grasp_policy.h"
#include "servo/arm_servo.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {

class MissionEvaluator;
class PlatformCollision;

/// One arm's servo and grasp sequence as the mission config sets them: the
/// servo settings for its joint count, vias through the zero and home poses,
/// kept clear of the safe volume and of the other arm (at its measured joints
/// *q_other_rad) by servo_margin_m; the sequence's pre-catch pose
/// precatch_distance_m back along the approach.
struct ArmController {
  std::unique_ptr<ArmServo> servo;
  std::unique_ptr<GraspSequence> sequence;  ///< drives `servo`
};
ArmController MakeArmController(const MissionConfig& config, const Platform& platform, Side side,
                                const PlatformCollision& collision,
                                const Eigen::VectorXd* q_other_rad, double precatch_distance_m);

/// The object as the arms follow it this cycle.
struct FollowView {
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();  ///< the object now, in d
  double stamp_s = 0.0;               ///< when that pose was observed (targets age from it)
  bool object_held_in_world = false;  ///< briefly lost: held at its last world pose
  bool holds[2] = {false, false};     ///< the grippers' last readings (left, right)
};

class GraspArms {
 public:
  /// `q` (two measured joint vectors, updated by the caller every cycle),
  /// `platform`, `planner` and `collision` must outlive the arms; `log` writes
  /// one line at the present time; `evaluator` may be null (no simulation).
  GraspArms(const Platform& platform, const GraspPlanner& planner,
            const PlatformCollision& collision, const MissionConfig& config,
            const Eigen::VectorXd* q, MissionEvaluator* evaluator,
            std::function<void(const std::string&)> log);

  /// A new plan: both arms follow `grasp` (planned with the object at dMo)
  /// from their pre-catch poses, held there until GoIn.
  void Start(const DualGrasp& grasp, const Eigen::Isometry3d& dMo, double t_s);
  /// A switch to `grasp`: arms whose pair changed go back to their pre-catch poses.
  void Switch(const DualGrasp& grasp, const Eigen::Isometry3d& dMo, const SwitchState& before,
              double t_s);
  /// Arm a alone aims at `g` and goes straight in (the other holds the object).
  void Aim(int a, const ArmGrasp& g, double t_s);
  /// Seconds arm a's servo has found no way to its target (unreachable, or
  /// still searching for one) at t_s, since its last Aim or motion; < 0: it moves.
  double unreachable_for_s(int a, double t_s) const {
    return unreachable_since_s_[a] < 0 ? -1.0 : t_s - unreachable_since_s_[a];
  }
  /// Both arms leave their pre-catch poses and move in.
  void GoIn();
  /// After a failed attempt: the servos' IK seeded with the home poses.
  void SeedHome();
  /// Both arms hold where they are (their measured joints as targets); the
  /// servos' next commands start from rest.
  void Hold(ArmsDriver* driver);

  /// One servo cycle following `followed`: targets, sequences, joint and
  /// gripper commands. The cause when an arm's joint readings are invalid
  /// (the caller stops the mission), else none.
  std::optional<std::string> Step(double t_s, double dt_s, const FollowView& view,
                                  const SwitchState& followed, ArmsDriver* driver);
  /// One cycle servoing both arms home; true once both are within the
  /// policy's home tolerance. Sets *emergency on invalid joint readings.
  bool Retract(double t_s, double dt_s, ArmsDriver* driver, std::optional<std::string>* emergency);

  GraspPhase phase(int a) const { return sequence_[a]->phase(); }
  /// Arm a's grasp target in its base this cycle (after Step).
  const Eigen::Isometry3d& grasp_target_bMg(int a) const { return reached_bMg_[a]; }
  /// Both arms at their pre-catch poses or past them (AtOrPastPreCatch).
  bool both_at_precatch() const {
    return AtOrPastPreCatch(sequence_[0]->phase(), sequence_[0]->at_precatch()) &&
           AtOrPastPreCatch(sequence_[1]->phase(), sequence_[1]->at_precatch());
  }

 private:
  /// The followed pair of arm a solved again for the object at dMo, on the
  /// IK branch it was followed on. True with the solution in solved_[a].
  bool SolveFollowed(int a, int pair, const Eigen::Isometry3d& dMo, double t_s);
  /// When the followed pair is out of reach for this instant: arm a's last
  /// targets carried with the object (now at bMo in its base) as far as the
  /// arm reaches them, position first (its closed-form IK nearest the last
  /// targets' joints, on their branch). True with the targets set.
  bool CarryWithObject(int a, const Eigen::Isometry3d& bMo, double t_s);
  void SetGrasps(const DualGrasp& grasp, const Eigen::Isometry3d& dMo, double t_s);

  const Platform& platform_;
  const GraspPlanner& planner_;
  const GraspPolicyConfig policy_;
  const Eigen::VectorXd* q_;
  MissionEvaluator* evaluator_;
  std::function<void(const std::string&)> log_;
  std::unique_ptr<ArmServo> servo_[2];
  std::unique_ptr<GraspSequence> sequence_[2];
  Eigen::Isometry3d oMg_[2];  // the tool at the grasp, in the object frame
  Eigen::Isometry3d oMp_[2];  // the tool at the pre-catch pose
  const ArmIk ik_[2];
  // The followed pair's last targets the arm reaches (in b), per arm.
  Eigen::Isometry3d reached_bMg_[2], reached_bMp_[2];
  // The targets of the last exact solution in the object frame (anchored:
  // known), which CarryWithObject moves with the object.
  Eigen::Isometry3d anchor_oMg_[2], anchor_oMp_[2];
  bool anchored_[2] = {false, false};
  Eigen::VectorXd reached_q_grasp_[2], reached_q_precatch_[2];
  bool has_reached_[2] = {false, false};    // solved since the pair was set
  double reached_stamp_s_[2] = {0.0, 0.0};  // when reached_q_grasp_ was last solved
  ArmGrasp solved_[2];                      // this cycle's solution (SolveFollowed)
  bool switch_pending_[2] = {false, false};
  ServoStatus last_status_[2] = {ServoStatus::kNoTarget, ServoStatus::kNoTarget};
  double unreachable_since_s_[2] = {-1.0, -1.0};  // < 0: the servo finds its way
  double error_m_[2] = {0.0, 0.0};                // the servo's last distance to its target
  double at_grasp_since_s_[2] = {-1.0, -1.0};     // < 0: not waiting at the grasp pose
};

}  // namespace aerograsp
