// The mission's grasp, scheduled: while the global machine is grasping, it
// plans when the policy says so, has the arms follow the chosen dual grasp,
// re-evaluates it and switches when the policy says so, re-aims a free arm,
// ends failed attempts and sends the arms home before the next plan. Every
// decision is the grasp policy's (mission/grasp_policy.h); this class carries
// them out. The planner never runs inside the servo cycle: plans, re-aims and
// re-evaluations are asked of it on a worker thread and their answers used one
// re-evaluation period (of the mission's clock) after they were asked, so the
// same seed flies the same mission however fast the worker is.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>

#include "app/runtime/mission_arms.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_record.h"
#include "app/runtime/mission_runner.h"
#include "grasp/planner.h"
#include "hardware/arms_driver.h"
#include "mission/grasp_policy.h"
#include "mission/state_machines.h"

namespace aerograsp {

class MissionEvaluator;
class PlatformCollision;
class TrackedObject;

/// The state machines the grasp drives (owned by the runner).
struct GraspMachines {
  GlobalMachine* global = nullptr;
  const VisionMachine* vision = nullptr;
  PlannerMachine* planner = nullptr;
  ArmsMachine* arms = nullptr;
};

class GraspScheduler {
 public:
  /// Everything given must outlive the scheduler. `q`: the two measured joint
  /// vectors (updated by the runner each cycle); `dMo_now()`: the object in
  /// the body frame now; `evaluator` and `record` may be null.
  GraspScheduler(const MissionConfig& config, const Platform& platform, const GraspPlanner& planner,
                 const PlatformCollision& collision, const Eigen::VectorXd* q,
                 TrackedObject* object, GraspMachines machines, ArmsDriver* driver,
                 MissionEvaluator* evaluator, MissionResult* result, MissionRecord* record,
                 std::function<Eigen::Isometry3d()> dMo_now,
                 std::function<void(const std::string&)> emergency,
                 std::function<void(const std::string&)> log);
  ~GraspScheduler();

  /// The planner machine's cycle: plan, advance or end the attempt, give up.
  /// Asks the planner on a worker and uses its answer when it is due.
  void Plan(double t_s);
  /// The background re-evaluation at reevaluate_rate_hz and its switches.
  void Reevaluate(double t_s);
  /// The arms' cycle: following the grasp, or going home after a failed attempt.
  void Servo(double t_s, double dt_s);
  /// Waits for the planner's answers due at t_s, before Plan and Reevaluate
  /// take them: on the simulated clock the worker may lag behind (on the wall
  /// clock they are long done), and the loop waits here, outside the servo
  /// cycle, as it waits for perception.
  void AwaitDue(double t_s);
  /// Waits for a plan or re-evaluation in flight (the mission ends).
  void Wait();

  /// True while an attempt runs (servoing, at the pre-catch poses, grasping).
  bool active() const;
  /// Both grippers hold the object: the grasp is done.
  bool holding() const { return holding_; }
  /// The contact pairs followed now (-1: none for that arm).
  const SwitchState& followed() const { return policy_.followed; }
  /// Either gripper held the object at its last reading.
  bool a_gripper_holds() const { return a_gripper_holds_; }

 private:
  /// A plan and what it was asked.
  struct AskedPlan {
    PlanQuery query;
    PlanResult result;
  };
  /// What a plan is asked for: a dual grasp, or a re-aim while arm `holder` holds.
  static constexpr int kForDualGrasp = -1;

  PlanQuery Query() const;
  /// The plan for `purpose` (kForDualGrasp, or the holding arm of a re-aim)
  /// once it is due: asks one on the worker (the object and the arms now) when
  /// none is in flight for that purpose and returns nothing until one
  /// re-evaluation period has passed; then waits for the worker if it is not
  /// done yet and returns its answer.
  std::optional<AskedPlan> DuePlan(double t_s, int purpose);
  /// Drops a plan in flight (waits for the worker to finish it).
  void DropPlan();
  /// Re-evaluation runs: an attempt is active and no arm holds the object alone.
  bool Reevaluating() const;
  bool StartPlan(double t_s, const AskedPlan& plan);
  /// One gripper holds the object, the other closed on nothing: the free arm
  /// aims at the pair the policy ranks first in `plan` among those clearing
  /// the holding arm. False when there is none.
  bool AimFreeArm(double t_s, int holding, const AskedPlan& plan);
  void StopArms(double t_s, const std::string& cause);

  const MissionConfig& config_;
  const GraspPlanner& planner_;
  const PlatformCollision& collision_;
  const Eigen::VectorXd* q_;
  TrackedObject* object_;
  GraspMachines sm_;
  ArmsDriver* driver_;
  MissionResult* result_;
  MissionRecord* record_;
  std::function<Eigen::Isometry3d()> dMo_now_;
  std::function<void(const std::string&)> emergency_, log_;
  GraspArms arms_;

  GraspPolicyState policy_;
  std::future<PlanResult> planning_;  // the plan in flight
  PlanQuery planning_query_;          // ... what it was asked
  int planning_for_ = kForDualGrasp;  // ... its purpose
  double planning_due_s_ = 0.0;       // ... when its answer is used
  bool plan_wanted_ = false;          // DuePlan was called in this cycle
  double next_reevaluate_s_ = 0.0;
  // The free arm's re-aim search: when it first found no pair (< 0: it has
  // not failed), and when it is due again.
  double reaim_failed_since_s_ = -1.0;
  double next_reaim_s_ = 0.0;
  std::future<SwitchDecision> reevaluating_;
  Eigen::Isometry3d reevaluate_dMo_ = Eigen::Isometry3d::Identity();
  double planning_since_s_ = -1.0;
  bool logged_no_grasp_ = false;
  bool a_gripper_holds_ = false;
  bool free_closed_empty_ = false;          // last cycle: the free gripper had closed on nothing
  bool gripper_holds_[2] = {false, false};  // read by Plan this cycle
  bool holding_ = false;
  bool retracting_ = false;  // the arms go home after a failed attempt
};

}  // namespace aerograsp
