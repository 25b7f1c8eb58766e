#include "app/mission_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <memory>
#include <thread>

#include "app/mission_config.h"
#include "app/statistics.h"
#include "core/collision.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "detection/object_tracker.h"
#include "detection/perception_config.h"
#include "grasp/planner.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"
#include "mission/state_machines.h"
#include "servo/collision_predicate.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using WallClock = std::chrono::steady_clock;

constexpr Side kSides[2] = {Side::kLeft, Side::kRight};
/// Consecutive re-evaluations (1 s at 5 Hz) that find the followed pair unreachable before it is
/// left: meanwhile each servo cycle solves the pair again where the object is (Servo()).
constexpr int kUnreachableToSwitch = 5;
/// Joint change (rad) between servo cycles beyond which a re-solved grasp is another branch.
constexpr double kBranchJumpRad = 0.15;
/// ... plus this much per second since the last accepted solution (the object moved meanwhile).
constexpr double kBranchDriftRadPerS = 0.5;
/// An arm this near its home pose (tool position, m) is back.
constexpr double kHomeToleranceM = 0.01;
/// Times the free arm is aimed again while the other holds, per attempt.
constexpr int kMaxReaims = 3;
const char* const kArmNames[2] = {"left", "right"};

/// The estimate (filtered in the world) moved on to t_s with its velocity
/// (at most 0.2 s ahead).
Eigen::Isometry3d PredictWmo(const ObjectEstimate& e, double t_s) {
  Eigen::Isometry3d wMo = e.fMo;
  wMo.translation() += e.v_f * std::clamp(t_s - e.stamp_s, 0.0, 0.2);
  return wMo;
}

/// One frame's result with the truth at its stamp (NaN without a world).
struct Perceived {
  FrameReport report;
  Eigen::Isometry3d dMo_truth = Eigen::Isometry3d::Identity();
  bool has_truth = false;
  Eigen::Isometry3d wMd = Eigen::Isometry3d::Identity();  ///< the vehicle when the frame was taken
  std::shared_ptr<RgbdFrame> frame;
};

/// Everything the loop needs, built before take-off.
class Mission {
 public:
  Mission(const MissionOptions& options, MissionRecord* record, std::ostream* log);
  MissionResult Run();

 private:
  void Log(double t_s, const std::string& line);
  void OnTransition(const StateTransition& t);
  double Now() const;
  /// Advances the clock by one servo period (simulated) or waits for it (real).
  void Tick();
  void Emergency(const std::string& cause);

  void Perception();
  void HandlePerceived(Perceived p);
  void Vehicle();
  void Planner();
  void Reevaluate();
  void Servo();
  void Safety();
  /// Logs how far the closing gripper is from its grasp on the true object (simulation).
  void LogClosing(int a, const Eigen::Isometry3d& dMo_est);
  /// Simulation only: where the closed gripper is on the true object.
  void LogClosed(int a);
  void SendSetpoint(const Eigen::Vector3d& p_w);
  bool StartPlan();
  /// One gripper holds the object, the other closed on nothing: the holding
  /// one stays closed (the object stays up) and the free arm is aimed at the
  /// feasible pair nearest its joints that clears the holding arm. False
  /// when there is none.
  bool AimFreeArm(int holding);
  /// The followed grasps, fixed to the object (planned with the object at dMo).
  void SetGrasps(const DualGrasp& grasp, const Eigen::Isometry3d& dMo);
  /// The followed pair of arm a solved again for the object at dMo, on the
  /// IK branch it was followed on. True with the solution in solved_[a].
  bool SolveFollowed(int a, const Eigen::Isometry3d& dMo);
  void StopArms(const std::string& cause);
  /// After a failed attempt: each arm servoed back to its home pose (out of
  /// the camera's view), then held.
  void Retract();
  Eigen::Isometry3d dMoNow() const;
  /// Arm a's tool in the body frame, at its measured joints.
  Eigen::Isometry3d dMe(int a) const;
  /// True while the object is briefly lost and held at its last world pose.
  bool HoldingObjectInWorld() const;
  PlanQuery Query() const;

  MissionConfig config_;
  MissionRecord* record_;
  std::ostream* log_;
  MissionResult result_;

  std::unique_ptr<Hardware> hw_;
  World* world_ = nullptr;
  std::unique_ptr<ObjectModel> object_;
  std::unique_ptr<ObjectTracker> tracker_;
  std::unique_ptr<GraspPlanner> planner_;
  std::unique_ptr<PlatformCollision> collision_;
  Eigen::VectorXd q_[2];  // measured joints, read by the other arm's forbidden predicate
  std::unique_ptr<ArmServo> servo_[2];
  std::unique_ptr<GraspSequence> sequence_[2];

  GlobalMachine global_;
  VehicleMachine vehicle_;
  VisionMachine vision_;
  PlannerMachine planner_sm_;
  ArmsMachine arms_;

  // Clock and rates.
  double dt_s_ = 0.01;
  double t0_wall_s_ = 0.0;
  double next_frame_s_ = 0.0, frame_period_s_ = 1.0 / 30.0;
  double next_setpoint_s_ = 0.0;
  double next_reevaluate_s_ = 0.0;

  // Perception in flight: started at a frame, collected at the next.
  std::future<Perceived> perceiving_;
  ObjectEstimate estimate_;
  double lost_since_s_ = -1.0;
  double last_found_stamp_s_ = 0.0;
  bool have_wMo_ = false;  // the object was found within the geofence once
  Eigen::Isometry3d wMo_last_ = Eigen::Isometry3d::Identity();  // at the last found frame
  bool logged_beyond_ = false;
  Eigen::Vector3d object_w_filtered_ = Eigen::Vector3d::Zero();
  std::vector<double> perception_ms_, render_ms_;
  double sq_position_ = 0.0, sq_rotation_ = 0.0;
  int truth_frames_ = 0;

  // Vehicle.
  Eigen::Vector3d waypoint_w_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d setpoint_w_ = Eigen::Vector3d::Zero();
  enum class Leg { kApproach, kTrack, kLift, kHome } leg_ = Leg::kApproach;
  double hover_since_s_ = -1.0;

  // Planner and grasp.
  std::future<SwitchDecision> reevaluating_;
  Eigen::Isometry3d reevaluate_dMo_ = Eigen::Isometry3d::Identity();
  SwitchState choice_;
  int unreachable_in_a_row_ = 0;
  int holding_arm_ = -1;          // while one gripper holds and the other re-aims: its index
  bool a_gripper_holds_ = false;  // either gripper, as last read (Planner)
  int reaims_ = 0;                // re-aims of the free arm in this attempt
  Eigen::Isometry3d eMo_held_ = Eigen::Isometry3d::Identity();  // the object in the holding gripper
  Eigen::Isometry3d oMg_[2];  // the tool at the grasp, in the object frame
  Eigen::Isometry3d oMp_[2];  // the tool at the pre-catch pose
  // The followed pair's last targets the planner's IK reached (in b), per arm.
  Eigen::Isometry3d reached_bMg_[2], reached_bMp_[2];
  Eigen::VectorXd reached_q_grasp_[2];
  bool has_reached_[2] = {false, false};    // solved since the pair was set
  double reached_stamp_s_[2] = {0.0, 0.0};  // when reached_q_grasp_ was last solved
  ArmGrasp solved_[2];                      // this cycle's solution (SolveFollowed)
  bool switch_pending_[2] = {false, false};
  ServoStatus last_status_[2] = {ServoStatus::kNoTarget, ServoStatus::kNoTarget};
  double planning_since_s_ = -1.0;
  bool logged_no_grasp_ = false;
  bool holding_ = false;
  bool retracting_ = false;  // the arms go home after a failed attempt

  // Safety.
  bool in_safe_volume_[2] = {false, false};
  int snapshot_priority_ = 0;
};

Mission::Mission(const MissionOptions& options, MissionRecord* record, std::ostream* log)
    : record_(record),
      log_(log),
      global_([this](const StateTransition& t) { OnTransition(t); }),
      vehicle_([this](const StateTransition& t) { OnTransition(t); }),
      vision_([this](const StateTransition& t) { OnTransition(t); }),
      planner_sm_(1, {}),
      arms_([this](const StateTransition& t) { OnTransition(t); }) {
  const std::string config_path =
      options.config_path.empty() ? DataPath("config/mission_default.yaml") : options.config_path;
  config_ = MissionConfig::Load(config_path);
  if (options.timeout_s > 0) config_.timeout_s = options.timeout_s;
  planner_sm_ =
      PlannerMachine(config_.max_attempts, [this](const StateTransition& t) { OnTransition(t); });
  if (options.arm_type != "4dof" && options.arm_type != "6dof") {
    throw ConfigError("--arm: '" + options.arm_type + "' is not one of 4dof, 6dof");
  }
  const std::string platform_path = DataPath("config/platform_" + options.arm_type + ".yaml");
  HardwareConfig hw_config;
  if (options.hardware_path.empty()) {
    hw_config = HardwareConfig::InProcessSimulation(platform_path, config_.world);
  } else {
    hw_config = HardwareConfig::Load(options.hardware_path);
    hw_config.world = config_.world;  // simulated devices fly the mission's world
  }
  const auto adjust = [&](WorldConfig* w) {
    if (!options.object.empty()) w->object.name = options.object;
    if (!options.motion.empty()) w->object.motion = options.motion;
    if (options.object_speed_mps >= 0) w->object.speed_mps = options.object_speed_mps;
    if (options.sway_amplitude_m >= 0) {
      w->vehicle.sway_amplitude_m = Eigen::Vector3d(1.0, 1.0, 2.0 / 3.0) * options.sway_amplitude_m;
    }
    if (options.sway_frequency_hz >= 0)
      w->vehicle.sway_frequency_hz.setConstant(options.sway_frequency_hz);
  };
  hw_ = Hardware::Open(hw_config, options.seed, adjust);
  for (int a = 0; a < 2;
       ++a) {  // camera-to-arm calibrations (calibration_left / _right): dMb = dMc * cMb
    if (config_.calibrated_cMb[a])
      hw_->SetArmBase(kSides[a], hw_->platform().dMc() * *config_.calibrated_cMb[a]);
  }
  world_ = hw_->world();
  const Platform& platform = hw_->platform();

  object_ = std::make_unique<ObjectModel>(
      world_ ? world_->object()
             : ObjectModel::Load(options.object.empty() ? "crawler" : options.object));
  std::unique_ptr<BoxDetector> detector;
  const fs::path onnx = fs::path(object_->source).parent_path() / "detector.onnx";
  if (fs::exists(onnx)) detector = std::make_unique<BoxDetector>(onnx.string());
  const PerceptionOptions perception =
      config_.perception.empty() ? PerceptionOptions{} : LoadPerceptionOptions(config_.perception);
  tracker_ = std::make_unique<ObjectTracker>(*object_, perception, std::move(detector));

  GraspPlannerConfig planner_config;
  // Contacts at least 2.5 cm behind the tool point: the closing line then
  // crosses the object even with the few millimetres of pose and tracking
  // error left in flight (a pair at the tool point itself closes on air).
  planner_config.depth_min_m = 0.025;
  // ... and up to the pads' roots (0.02 m inside the tips, 0.12 m long): a
  // followed pair is then exactly solvable in about two thirds of the close's
  // servo cycles instead of a third (the contacts may sit deeper as the object
  // sways), so the target is fresh when the fingers close (seeds 1-30: 29
  // grasp, 24 with 0.08).
  planner_config.depth_max_m = 0.10;
  planner_config.edge_margin_m = config_.grasp_edge_margin_m;
  planner_config.Validate(config_.source, platform.config().gripper);
  GraspObject grasp_object{object_->name, object_->mesh_o, object_->mass_kg,
                           object_->center_of_mass_o};
  ContactSet contacts =
      ComputeContactPairs(object_->mesh_o, platform.config().gripper, planner_config.contacts);
  planner_ = std::make_unique<GraspPlanner>(platform, std::move(grasp_object), std::move(contacts),
                                            planner_config);

  collision_ = std::make_unique<PlatformCollision>(platform);
  for (int a = 0; a < 2; ++a) {
    q_[a] = hw_->arms().JointPositions(kSides[a]);
    const ArmModel& arm = platform.arm(kSides[a]);
    ServoConfig servo_config;
    servo_config.via_rad = {arm.Clamp(Eigen::VectorXd::Zero(arm.dof())), platform.home(kSides[a])};
    GraspSequenceConfig sequence_config;
    if (arm.dof() < 6) {
      // A 4-DoF arm's approach axis follows from the tool position: when the
      // object moves a centimetre the planned axis is off by a degree or two
      // and no joint goal meets it exactly. Position is met exactly; the axis
      // and the roll about it within a few degrees (a parallel gripper closes
      // as well on a slightly tilted approach).
      servo_config.ik.tolerance = PoseTolerance{1e-4, 0.10, 0.15};
    }
    // The object sways +-3 cm at 0.5 Hz (about 9 cm/s) and the arm follows a
    // frame period and a servo lag behind it: a few millimetres of tracking
    // error remain, which the gripper's clearance (finger_clearance_m) takes.
    sequence_config.precatch_tolerance.position_m = 0.01;
    sequence_config.precatch_timeout_s = 10.0;  // 0.35 m from home while the target sways
    sequence_config.grasp_timeout_s = 5.0;
    servo_config.unreachable_retry_s = 0.1;  // the sway brings a target back within a cycle or two
    // A first-order tracker of gain k follows a sway of w = 2 pi 0.5 Hz with an
    // error of about A w / sqrt(w^2 + k^2): 2.2 cm of a 3 cm sway at the
    // default k = 3/s, 0.6 cm at 15/s.
    servo_config.gain_per_s = 15.0;
    sequence_config.grasp_tolerance.position_m = 0.006;
    servo_[a] = std::make_unique<ArmServo>(
        arm, servo_config,
        MakeCollisionPredicate(*collision_, kSides[a], config_.servo_margin_m, &q_[1 - a]));
    sequence_config.precatch_distance_m = planner_config.precatch_distance_m;
    sequence_config.close_time_s = platform.config().gripper.close_time_s;
    sequence_[a] = std::make_unique<GraspSequence>(servo_[a].get(), sequence_config);
  }
  dt_s_ = 1.0 / config_.servo_rate_hz;
  if (world_) frame_period_s_ = 1.0 / world_->config().camera.frame_rate_hz;
  if (record_) {
    record_->object_name = object_->name;
    record_->object_mesh_o = object_->mesh_o;
    for (int a = 0; a < 2; ++a) record_->joint_names[a] = platform.arm(kSides[a]).joint_names();
  }
}

double Mission::Now() const {
  if (world_) return world_->now_s();
  return std::chrono::duration<double>(WallClock::now().time_since_epoch()).count() - t0_wall_s_;
}

void Mission::Tick() {
  if (world_) {
    hw_->StepSimulation(dt_s_);
    return;
  }
  const double next = (std::floor(Now() / dt_s_) + 1.0) * dt_s_;
  std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.0, next - Now())));
}

void Mission::Log(double t_s, const std::string& line) {
  if (log_) *log_ << fmt::format("[{:8.3f} s] {}\n", t_s, line);
}

void Mission::OnTransition(const StateTransition& t) {
  Log(t.t_s, fmt::format("{:<7} {} -> {}: {}", t.machine, t.from, t.to, t.cause));
  if (record_) record_->transitions.push_back({t.t_s, t.machine, t.from, t.to, t.cause});
}

void Mission::Emergency(const std::string& cause) {
  const double t = Now();
  ++result_.emergency_stops;
  arms_.EmergencyStop(t, cause);
  global_.Emergency(t, cause);
  try {
    hw_->arms().Stop();
  } catch (const std::exception& e) {
    Log(t, std::string("arms stop failed: ") + e.what());
  }
  try {
    const CommandAck ack = hw_->autopilot().Hold();
    if (!ack.accepted) Log(t, "autopilot refused hold: " + ack.reason);
  } catch (const std::exception& e) {
    Log(t, std::string("autopilot hold failed: ") + e.what());
  }
}

bool Mission::HoldingObjectInWorld() const {
  return have_wMo_ && vision_.state() != VisionState::kFound && lost_since_s_ >= 0 &&
         Now() - lost_since_s_ <= config_.lost_timeout_s;
}

Eigen::Isometry3d Mission::dMe(int a) const {
  const Side side = kSides[a];
  return hw_->platform().dMb(side) * hw_->platform().arm(side).ForwardKinematics(q_[a]);
}

Eigen::Isometry3d Mission::dMoNow() const {
  // Held by one gripper: the object goes where that gripper goes.
  if (holding_arm_ >= 0) return dMe(holding_arm_) * eMo_held_;
  // Briefly lost (the grippers hide the object as they close in): the object
  // stays where it was last seen in the world, and the vehicle's own pose
  // carries it into the body frame through the sway.
  const Eigen::Isometry3d dMw = hw_->autopilot().State().wMd.inverse();
  if (HoldingObjectInWorld()) return dMw * wMo_last_;
  // The filter runs in the world (the object crawls slowly there, while the
  // camera sways): the vehicle's pose now brings it into the body.
  return dMw * PredictWmo(estimate_, Now());
}

PlanQuery Mission::Query() const {
  PlanQuery query;
  query.dMo = dMoNow();
  query.q_left = q_[0];
  query.q_right = q_[1];
  return query;
}

void Mission::SendSetpoint(const Eigen::Vector3d& p_w) {
  const CommandAck ack = hw_->autopilot().SetPositionTarget(p_w, config_.yaw_rad);
  if (!ack.accepted) Log(Now(), "autopilot refused the setpoint: " + ack.reason);
}

// ---- Perception ---------------------------------------------------------------

void Mission::Perception() {
  const double t = Now();
  if (t + 1e-9 < next_frame_s_) return;
  next_frame_s_ += frame_period_s_;
  if (next_frame_s_ < t) next_frame_s_ = t + frame_period_s_;
  // Vision runs while the vehicle flies (the camera sees only the pad before),
  // nor once both grippers hold the object: nothing steers by it any more
  // (the lift and the flight home, about 10 s of a 25 s mission).
  auto wanted = [this] {
    const VehicleMode mode = vehicle_.state();
    return mode != VehicleMode::kIdle && mode != VehicleMode::kTakeOff &&
           global_.state() != GlobalState::kDone && global_.state() != GlobalState::kAborted &&
           !holding_;
  };
  // The frame is rendered while the tracker still works on the previous one
  // (the two take about as long); its result is handled at this frame's time
  // as before, so the mission does not change, only the wall time.
  std::shared_ptr<RgbdFrame> frame;
  Perceived job;
  if (wanted()) {
    frame = std::make_shared<RgbdFrame>();
    const WallClock::time_point render_start = WallClock::now();
    if (!hw_->camera().Grab(frame.get())) throw HardwareError("camera: the stream ended");
    render_ms_.push_back(
        std::chrono::duration<double, std::milli>(WallClock::now() - render_start).count());
    job.wMd = hw_->autopilot().State().wMd;
    if (world_) {
      job.dMo_truth = world_->wMd().inverse() * world_->wMo();
      job.has_truth = true;
    }
  }
  if (perceiving_.valid()) HandlePerceived(perceiving_.get());
  if (!frame || !wanted()) return;
  job.frame = frame;
  const CameraIntrinsics K = hw_->camera().intrinsics();
  const double scale = hw_->camera().depth_scale_m();
  // Briefly lost with the object held at its last world pose: that pose seeds
  // the tracker (a local ICP) instead of a global registration on the frame,
  // which costs ten times more and may lock onto clutter.
  if (HoldingObjectInWorld()) tracker_->SetInitialPose(hw_->platform().dMc().inverse() * dMoNow());
  ObjectTracker* tracker = tracker_.get();
  const Eigen::Isometry3d wMc = job.wMd * hw_->platform().dMc();
  perceiving_ =
      std::async(std::launch::async, [tracker, K, scale, wMc, job = std::move(job)]() mutable {
        job.report =
            tracker->Process(job.frame->color, job.frame->depth, job.frame->stamp_s, K, scale, wMc);
        return std::move(job);
      });
}

void Mission::HandlePerceived(Perceived p) {
  const double t = Now();
  ++result_.frames;
  result_.global_registrations += p.report.global_init ? 1 : 0;
  perception_ms_.push_back(p.report.times.total_ms);
  estimate_ = p.report.estimate;
  const bool found = estimate_.valid && estimate_.state == TrackState::kFound;
  const VisionSignal signal =
      vision_.Update(t, found,
                     found ? fmt::format("pose found (confidence {:.2f})", estimate_.confidence)
                           : fmt::format("pose lost (confidence {:.2f})", estimate_.confidence));
  if (found) {
    lost_since_s_ = -1.0;
    last_found_stamp_s_ = estimate_.stamp_s;
  } else if (lost_since_s_ < 0) {
    lost_since_s_ = t;
  }
  const Eigen::Isometry3d dMc = hw_->platform().dMc();
  const Eigen::Isometry3d dMo_est = dMc * estimate_.cMo;  // at the frame
  const Eigen::Vector3d object_w = estimate_.fMo.translation();
  const bool beyond = (object_w - config_.approach_w_m).norm() >
                      config_.tracking_radius_m + config_.grasp_dto_m.norm();
  if (found && beyond && !logged_beyond_) {
    logged_beyond_ = true;
    Log(t,
        fmt::format(
            "vision: the object is seen {:.2f} m from the approach waypoint, beyond the tracking "
            "radius: not followed",
            (object_w - config_.approach_w_m).norm()));
  }
  const double alpha =
      std::min(1.0, frame_period_s_ / config_.object_filter_s);  // low-pass gain per frame
  if (found && holding_arm_ >= 0) {
    // Held by one gripper the object moves with it: each frame's estimate
    // refines where it sits in that gripper (it was taken from the estimate
    // when the gripper closed, often while the fingers hid the object).
    Eigen::Isometry3d eMo = dMe(holding_arm_).inverse() * dMo_est;
    eMo.linear() =
        ClosestSymmetricRotation(eMo.linear(), eMo_held_.linear(), tracker_->model().symmetry);
    eMo_held_.translation() += alpha * (eMo.translation() - eMo_held_.translation());
    eMo_held_.linear() = Eigen::Quaterniond(eMo_held_.linear())
                             .slerp(alpha, Eigen::Quaterniond(eMo.linear()))
                             .normalized()
                             .toRotationMatrix();
  }
  if (found && !beyond) {
    logged_beyond_ = false;
    object_w_filtered_ =
        have_wMo_ ? object_w_filtered_ + alpha * (object_w - object_w_filtered_) : object_w;
    wMo_last_ = estimate_.fMo;
    have_wMo_ = true;
  }
  if (signal == VisionSignal::kLost) vehicle_.Lost(t);

  MissionSample s;
  s.t_s = p.frame->stamp_s;
  s.estimate_valid = estimate_.valid;
  s.found = found;
  if (estimate_.valid) s.dto_estimate_m = dMo_est.translation();
  if (p.has_truth) {
    s.dto_truth_m = p.dMo_truth.translation();
    if (estimate_.valid) {
      const Eigen::Matrix3d cRo_true = (dMc.inverse() * p.dMo_truth).linear();
      s.rotation_error_deg =
          SymmetricRotationError(estimate_.cMo.linear(), cRo_true, tracker_->model().symmetry) *
          180.0 / M_PI;
      // Accuracy where it matters: frames found while grasping (a lock on
      // clutter during the approach, beyond the geofence, is not followed).
      if (found && global_.state() == GlobalState::kGrasping) {
        sq_position_ += (s.dto_estimate_m - s.dto_truth_m).squaredNorm();
        sq_rotation_ += s.rotation_error_deg * s.rotation_error_deg;
        ++truth_frames_;
      }
    }
  }
  for (int a = 0; a < 2; ++a) {
    s.q_actual_rad[a] = q_[a];
    s.q_target_rad[a] = world_ ? world_->arm(kSides[a]).target_rad() : q_[a];
  }
  s.vehicle_w_m = hw_->autopilot().State().wMd.translation();
  if (!record_) return;
  record_->samples.push_back(s);
  // The report's camera frame: the last one before the grippers close with the
  // arms servoing, else the last with the object found.
  const PlannerState ps = planner_sm_.state();
  const int priority = !found ? 0
                       : (ps == PlannerState::kServoing || ps == PlannerState::kApproachPose ||
                          ps == PlannerState::kGrasping)
                           ? 2
                           : 1;
  if (priority > 0 && priority >= snapshot_priority_ && !holding_) {
    snapshot_priority_ = priority;
    MissionSnapshot snap;
    snap.t_s = p.frame->stamp_s;
    snap.color = p.frame->color;
    snap.K = hw_->camera().intrinsics();
    if (p.report.detection) {
      snap.has_box = true;
      snap.box_x0 = p.report.detection->box.x0;
      snap.box_y0 = p.report.detection->box.y0;
      snap.box_x1 = p.report.detection->box.x1;
      snap.box_y1 = p.report.detection->box.y1;
    }
    snap.has_pose = estimate_.valid;
    snap.cMo = estimate_.cMo;
    record_->snapshot = std::move(snap);
  }
}

// ---- Vehicle and global ---------------------------------------------------------

void Mission::Vehicle() {
  const double t = Now();
  const VehicleState vs = hw_->autopilot().State();
  if (!vs.link_ok) {
    Emergency("autopilot: the link is lost (no state for too long)");
    return;
  }
  const Eigen::Vector3d p_w = vs.wMd.translation();
  const Eigen::Matrix3d wRyaw =
      Eigen::AngleAxisd(config_.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto go_to = [&](const Eigen::Vector3d& w, Leg leg, const std::string& name) {
    waypoint_w_ = w;
    leg_ = leg;
    setpoint_w_ = w;
    vehicle_.GoTo(
        t, fmt::format("{}: waypoint [{:.2f}, {:.2f}, {:.2f}] m", name, w.x(), w.y(), w.z()));
  };
  const GlobalState g = global_.state();
  if (g == GlobalState::kAborted || g == GlobalState::kDone) return;

  switch (vehicle_.state()) {
    case VehicleMode::kIdle:
      if (g == GlobalState::kApproaching) {
        CommandAck ack = hw_->autopilot().Arm();
        if (ack.accepted) ack = hw_->autopilot().Takeoff(config_.takeoff_altitude_m);
        if (!ack.accepted) {
          global_.GiveUp(t, "the autopilot refused to take off: " + ack.reason);
          return;
        }
        vehicle_.TakeOff(t);
      }
      break;
    case VehicleMode::kTakeOff:
      if (vs.mode == FlightMode::kHold &&
          std::abs(-p_w.z() - config_.takeoff_altitude_m) < config_.arrive_tolerance_m) {
        vehicle_.Airborne(t);
        if (g == GlobalState::kApproaching) {
          go_to(config_.approach_w_m, Leg::kApproach, "approach");
        } else {
          go_to(Eigen::Vector3d(0.0, 0.0, p_w.z()), Leg::kHome, "home");
        }
      }
      break;
    case VehicleMode::kWaypoint:
      if ((p_w - waypoint_w_).norm() < config_.arrive_tolerance_m) {
        vehicle_.Arrived(t);
        hover_since_s_ = t;
        if (leg_ == Leg::kLift) {
          go_to(Eigen::Vector3d(0.0, 0.0, waypoint_w_.z()), Leg::kHome, "home");
        } else if (leg_ == Leg::kHome) {
          const CommandAck ack = hw_->autopilot().Land();
          if (!ack.accepted) {
            Emergency("the autopilot refused to land: " + ack.reason);
            return;
          }
          vehicle_.Land(t, "over the take-off point");
        }
      }
      break;
    case VehicleMode::kHover:
      if (g == GlobalState::kHoming) {
        go_to(p_w - Eigen::Vector3d(0.0, 0.0, config_.lift_m), Leg::kLift, "lift");
      } else if (vision_.state() == VisionState::kFound) {
        if (g == GlobalState::kApproaching) global_.Found(t, leg_ == Leg::kApproach);
        if (global_.state() == GlobalState::kGrasping && vehicle_.Found(t)) leg_ = Leg::kTrack;
      } else if (g == GlobalState::kGrasping && lost_since_s_ >= 0 &&
                 t - lost_since_s_ > config_.lost_timeout_s && leg_ == Leg::kTrack &&
                 holding_arm_ < 0) {
        go_to(config_.approach_w_m, Leg::kApproach, "search again");
      } else if ((g == GlobalState::kApproaching ||
                  (g == GlobalState::kGrasping && leg_ == Leg::kApproach)) &&
                 t - hover_since_s_ > config_.search_timeout_s) {
        global_.GiveUp(t, fmt::format("the object was {} in {:.0f} s at the approach waypoint",
                                      g == GlobalState::kApproaching ? "not found"
                                                                     : "lost and not found again",
                                      config_.search_timeout_s));
      }
      break;
    case VehicleMode::kTracking:
      if (g == GlobalState::kHoming) {
        go_to(p_w - Eigen::Vector3d(0.0, 0.0, config_.lift_m), Leg::kLift, "lift");
        break;
      }
      // An object a gripper holds moves with the vehicle: tracking it, the
      // vehicle would chase what it carries (and drag it off its pipe while
      // the other arm still tries).
      if (have_wMo_ && !a_gripper_holds_) {
        // Geofence: never farther than tracking_radius_m from the approach waypoint.
        const Eigen::Vector3d wanted = object_w_filtered_ - wRyaw * config_.grasp_dto_m;
        const Eigen::Vector3d off = wanted - config_.approach_w_m;
        setpoint_w_ = off.norm() <= config_.tracking_radius_m
                          ? wanted
                          : Eigen::Vector3d(config_.approach_w_m +
                                            off.normalized() * config_.tracking_radius_m);
      }
      if (planner_sm_.state() == PlannerState::kIdle && vision_.state() == VisionState::kFound) {
        const double off_m = (dMoNow().translation() - config_.grasp_dto_m).norm();
        if (off_m < config_.near_tolerance_m) planner_sm_.Start(t);
      }
      break;
    case VehicleMode::kLanding:
      if (vs.mode == FlightMode::kLanded || vs.mode == FlightMode::kDisarmed) {
        vehicle_.Landed(t);
        global_.Landed(t);
      }
      break;
  }
  // Setpoints while the companion flies the vehicle.
  const VehicleMode m = vehicle_.state();
  if ((m == VehicleMode::kWaypoint || m == VehicleMode::kHover || m == VehicleMode::kTracking) &&
      t + 1e-9 >= next_setpoint_s_) {
    next_setpoint_s_ = t + 1.0 / config_.setpoint_rate_hz;
    SendSetpoint(setpoint_w_);
  }
}

// ---- Grasp planner ----------------------------------------------------------------

bool Mission::AimFreeArm(int holding) {
  const double t = Now();
  const int free = 1 - holding;
  const PlanQuery query = Query();
  const PlanResult plan = planner_->Plan(query);
  const std::vector<ArmGrasp>& candidates = free == 0 ? plan.left : plan.right;
  const Eigen::VectorXd& q_held = q_[holding];
  const auto collide = [&](const Eigen::VectorXd& q_free) {
    return free == 0 ? collision_->ArmsCollide(q_free, q_held, planner_->config().arms_margin_m)
                     : collision_->ArmsCollide(q_held, q_free, planner_->config().arms_margin_m);
  };
  // Grasps clear of the faces' edges first (one near an end closes past it
  // with a few millimetres of error), then the nearest the arm's joints.
  const ArmGrasp* best = nullptr;
  for (const ArmGrasp& g : candidates) {
    if (collide(g.q_grasp) || collide(g.q_precatch)) continue;
    if (!best || std::make_pair(!g.clear_of_edges, g.cost_rad) <
                     std::make_pair(!best->clear_of_edges, best->cost_rad)) {
      best = &g;
    }
  }
  if (!best) {
    Log(t, fmt::format("planner: the {} gripper holds the object but no pair clears it for the {} "
                       "arm ({} feasible "
                       "for it{})",
                       kArmNames[holding], kArmNames[free], candidates.size(),
                       candidates.empty() ? "" : ", each too near the holding arm"));
    return false;
  }
  if (holding_arm_ < 0) eMo_held_ = dMe(holding).inverse() * query.dMo;
  holding_arm_ = holding;
  (free == 0 ? choice_.left_pair : choice_.right_pair) = best->pair;
  (holding == 0 ? choice_.left_pair : choice_.right_pair) = -1;  // the holding arm is not re-solved
  const ArmModel& arm = hw_->platform().arm(kSides[free]);
  reached_q_grasp_[free] = best->q_grasp;
  reached_stamp_s_[free] = t;
  reached_bMg_[free] = arm.ForwardKinematics(best->q_grasp);
  reached_bMp_[free] = arm.ForwardKinematics(best->q_precatch);
  has_reached_[free] = true;
  servo_[free]->SetSeedHints({best->q_precatch, best->q_grasp});
  sequence_[free]->Start(t);
  sequence_[free]->HoldAtPreCatch(false);
  ++result_.attempts;
  Log(t, fmt::format("planner: the {} gripper holds the object and stays closed; the {} arm "
                     "re-aims at pair {} "
                     "({} feasible for it)",
                     kArmNames[holding], kArmNames[free], best->pair, candidates.size()));
  return true;
}

bool Mission::StartPlan() {
  const double t = Now();
  const PlanQuery query = Query();
  const PlanResult plan = planner_->Plan(query);
  if (plan.ranked.empty()) {
    if (!logged_no_grasp_) {
      std::string why;
      for (int a = 0; a < 2; ++a) {
        const std::string r = DescribeReasons(a == 0 ? plan.left_stats : plan.right_stats);
        if (!r.empty()) why += fmt::format("; {}: {}", kArmNames[a], r);
      }
      Log(t, fmt::format("planner: no feasible dual grasp yet ({} left, {} right feasible{}; the "
                         "object {:.0f} mm from "
                         "its grasp point under the body); waiting",
                         plan.left.size(), plan.right.size(), why,
                         1e3 * (query.dMo.translation() - config_.grasp_dto_m).norm()));
      logged_no_grasp_ = true;
    }
    return false;
  }
  logged_no_grasp_ = false;
  const DualGrasp& best = plan.ranked.front();
  retracting_ = false;
  choice_ = {best.left.pair, best.right.pair};
  SetGrasps(best, query.dMo);
  for (int a = 0; a < 2; ++a) {
    sequence_[a]->Start(t);
    sequence_[a]->HoldAtPreCatch(true);
    switch_pending_[a] = false;
  }
  ++result_.attempts;
  arms_.Move(t, "servoing to the pre-catch poses");
  planner_sm_.Planned(
      t, fmt::format("pairs L{} R{} of {} ranked: epsilon {:.3f}, score {:.3f}", best.left.pair,
                     best.right.pair, plan.ranked.size(), best.epsilon, best.score));
  next_reevaluate_s_ = t + 1.0 / config_.reevaluate_rate_hz;
  return true;
}

void Mission::SetGrasps(const DualGrasp& grasp, const Eigen::Isometry3d& dMo) {
  has_reached_[0] = has_reached_[1] = false;
  // The tool frame the planner's joints reach, not the contact frame g: the
  // gripper is symmetric, so the planner may take g turned half a turn about
  // its approach axis, which a 4-DoF arm cannot reach as such.
  const ArmGrasp* arm_grasps[2] = {&grasp.left, &grasp.right};
  const Eigen::Isometry3d oMd = dMo.inverse();
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const Eigen::Isometry3d oMb = oMd * hw_->platform().dMb(side);
    oMg_[a] = oMb * hw_->platform().arm(side).ForwardKinematics(arm_grasps[a]->q_grasp);
    oMp_[a] = oMb * hw_->platform().arm(side).ForwardKinematics(arm_grasps[a]->q_precatch);
    reached_q_grasp_[a] = arm_grasps[a]->q_grasp;
    reached_stamp_s_[a] = Now();
    servo_[a]->SetSeedHints({arm_grasps[a]->q_precatch, arm_grasps[a]->q_grasp});
  }
}

void Mission::StopArms(const std::string& cause) {
  const double t = Now();
  arms_.Hold(t, cause);
  for (int a = 0; a < 2; ++a) {
    hw_->arms().SetJointTargets(kSides[a], q_[a]);
    hw_->arms().SetGripper(kSides[a], GripperCommand::kOpen);
  }
  a_gripper_holds_ = false;  // opened, neither holds
}

void Mission::Planner() {
  const double t = Now();
  if (global_.state() != GlobalState::kGrasping) return;
  const PlannerState state = planner_sm_.state();
  const bool active = state == PlannerState::kServoing || state == PlannerState::kApproachPose ||
                      state == PlannerState::kGrasping;
  if (state == PlannerState::kPlanning) {
    if (planning_since_s_ < 0) planning_since_s_ = t;
    if (vision_.state() == VisionState::kFound && StartPlan()) {
      planning_since_s_ = -1.0;
    } else if (t - planning_since_s_ > config_.planning_timeout_s) {
      global_.GiveUp(
          t, vision_.state() == VisionState::kFound
                 ? fmt::format("no feasible dual grasp within {:.0f} s", config_.planning_timeout_s)
                 : fmt::format("the object was not in view for {:.0f} s to plan again",
                               config_.planning_timeout_s));
    }
    return;
  }
  if (state == PlannerState::kFailed) {
    global_.GiveUp(t, "every grasp attempt failed");
    return;
  }
  if (!active) return;

  // Failures of an attempt: plan again.
  std::string retry;
  for (int a = 0; a < 2; ++a) {
    if (sequence_[a]->phase() == GraspPhase::kTimedOut) {
      retry = fmt::format("{} arm timed out", kArmNames[a]);
    }
  }
  if (lost_since_s_ >= 0 && t - lost_since_s_ > config_.lost_timeout_s && holding_arm_ < 0) {
    retry = fmt::format("object lost for {:.1f} s", t - lost_since_s_);
  }
  const bool done =
      sequence_[0]->phase() == GraspPhase::kDone && sequence_[1]->phase() == GraspPhase::kDone;
  // Each gripper read once per cycle (on hardware a read is a bus transaction).
  const GripperState gl = hw_->arms().Gripper(Side::kLeft), gr = hw_->arms().Gripper(Side::kRight);
  const bool held = gl.holding && gr.holding;
  a_gripper_holds_ = gl.holding || gr.holding;
  // One gripper holds: it stays closed (opened, it would drop the object).
  // Once it has closed and the other's attempt has ended (closed on nothing,
  // timed out, or the object hidden by the fingers), the free arm aims again.
  if (gl.holding != gr.holding) {
    const int holder = gl.holding ? 0 : 1;
    const GraspPhase free_phase = sequence_[1 - holder]->phase();
    const bool free_ended =
        free_phase == GraspPhase::kDone || free_phase == GraspPhase::kTimedOut || !retry.empty();
    if (sequence_[holder]->phase() != GraspPhase::kDone) {
      if (free_ended) return;  // still closing
    } else if (free_ended && reaims_ < kMaxReaims && AimFreeArm(holder)) {
      ++reaims_;
      return;
    }
  }
  if (done && !held) {
    retry = fmt::format(
        "the grippers closed without holding the object (left {} at {:.0f} mm, right {} at {:.0f} "
        "mm)",
        gl.holding ? "holds" : "empty", 1e3 * gl.aperture_m, gr.holding ? "holds" : "empty",
        1e3 * gr.aperture_m);
  }
  if (!retry.empty()) {
    holding_arm_ = -1;
    reaims_ = 0;
    planner_sm_.Retry(t, retry);
    StopArms("attempt ended: " + retry);
    // Held at their grasp poses the arms hide part of the object from the
    // camera; home, they are out of its view for the next search and plan.
    arms_.Move(t, "back home, out of the camera's view, to plan again");
    retracting_ = true;
    for (int a = 0; a < 2; ++a) servo_[a]->SetSeedHints({hw_->platform().home(kSides[a])});
    planning_since_s_ = t;
    return;
  }

  switch (state) {
    case PlannerState::kServoing:
      if (sequence_[0]->at_precatch() && sequence_[1]->at_precatch()) planner_sm_.AtPreCatch(t);
      break;
    case PlannerState::kApproachPose:
      if (planner_sm_.TimeIn(t) >= config_.settle_s) {
        planner_sm_.GoIn(t);
        for (auto& sequence : sequence_) sequence->HoldAtPreCatch(false);
      }
      break;
    case PlannerState::kGrasping:
      if (done && held) {
        planner_sm_.Closed(t);
        holding_ = true;
        result_.time_to_grasp_s = t;
        arms_.Hold(t, "grasped: holding the object");
        global_.Grasped(t);
      }
      break;
    default:
      break;
  }
}

void Mission::Reevaluate() {
  const double t = Now();
  const PlannerState state = planner_sm_.state();
  const bool active = global_.state() == GlobalState::kGrasping &&
                      (state == PlannerState::kServoing || state == PlannerState::kApproachPose ||
                       state == PlannerState::kGrasping);
  if (!active || holding_arm_ >= 0) {  // (one arm holding: its pair is not to be switched)
    if (reevaluating_.valid()) reevaluating_.get();  // an answer for a plan that has ended
    return;
  }
  if (t + 1e-9 < next_reevaluate_s_) return;
  next_reevaluate_s_ = t + 1.0 / config_.reevaluate_rate_hz;
  if (reevaluating_.valid()) {
    const SwitchDecision decision = reevaluating_.get();
    const bool closing =
        sequence_[0]->phase() == GraspPhase::kClose || sequence_[0]->phase() == GraspPhase::kDone ||
        sequence_[1]->phase() == GraspPhase::kClose || sequence_[1]->phase() == GraspPhase::kDone;
    // A pair unreachable at one re-evaluation may be reachable at the next (the
    // sway brings the object back): switch only when it stays unreachable.
    unreachable_in_a_row_ =
        decision.status == SwitchDecision::Status::kSwitch ? unreachable_in_a_row_ + 1 : 0;
    if (decision.status == SwitchDecision::Status::kSwitch && !closing &&
        unreachable_in_a_row_ >= kUnreachableToSwitch) {
      unreachable_in_a_row_ = 0;
      const int pairs[2] = {decision.grasp.left.pair, decision.grasp.right.pair};
      const int before[2] = {choice_.left_pair, choice_.right_pair};
      SetGrasps(decision.grasp, reevaluate_dMo_);
      for (int a = 0; a < 2; ++a) {
        switch_pending_[a] = pairs[a] != before[a];
        sequence_[a]->HoldAtPreCatch(true);
      }
      choice_ = decision.next;
      ++result_.grasp_switches;
      if (record_) record_->switches.push_back({t, pairs[0], pairs[1], decision.reason});
      planner_sm_.Switched(
          t, fmt::format("switch to pairs L{} R{}: {}", pairs[0], pairs[1], decision.reason));
    } else if (decision.status == SwitchDecision::Status::kKeep) {
      choice_ = decision.next;
    }
  }
  reevaluate_dMo_ = dMoNow();
  PlanQuery query = Query();
  query.dMo = reevaluate_dMo_;
  const GraspPlanner* planner = planner_.get();
  const SwitchState choice = choice_;
  reevaluating_ = std::async(
      std::launch::async, [planner, query, choice] { return planner->Reevaluate(query, choice); });
}

// ---- Servo and safety ---------------------------------------------------------------

bool Mission::SolveFollowed(int a, const Eigen::Isometry3d& dMo) {
  const double t = Now();
  const int pair = a == 0 ? choice_.left_pair : choice_.right_pair;
  Infeasibility why = Infeasibility::kNone;
  if (!planner_->EvaluateArm(kSides[a], pair, dMo, q_[a], &solved_[a], &why)) return false;
  // Another IK branch or depth is not followed (with a fixed allowance, a pair
  // out of reach for a while stayed refused for good, its stale target standing).
  if (!OnSameIkBranch(solved_[a].q_grasp, reached_q_grasp_[a], kBranchJumpRad, kBranchDriftRadPerS,
                      t - reached_stamp_s_[a])) {
    return false;
  }
  reached_q_grasp_[a] = solved_[a].q_grasp;
  reached_stamp_s_[a] = t;
  return true;
}

void Mission::Servo() {
  const double t = Now();
  if (!arms_.commands_allowed() || global_.state() != GlobalState::kGrasping) return;
  const PlannerState state = planner_sm_.state();
  if (retracting_ && state == PlannerState::kPlanning) {
    Retract();
    return;
  }
  if (state != PlannerState::kServoing && state != PlannerState::kApproachPose &&
      state != PlannerState::kGrasping) {
    return;
  }
  const Eigen::Isometry3d dMo = dMoNow();
  const int pairs[2] = {choice_.left_pair, choice_.right_pair};
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const Eigen::Isometry3d bMo = hw_->platform().dMb(side).inverse() * dMo;
    // The followed pair solved again for the object where it is now (the
    // planner's closed-form grasp-axis IK): targets the arm reaches exactly,
    // and their joints as the servo's IK seeds. When it is out of reach for
    // this instant, the last reachable targets stand (and re-evaluation
    // decides whether to switch).
    if (pairs[a] >= 0 && SolveFollowed(a, dMo)) {
      const ArmModel& arm = hw_->platform().arm(side);
      const ArmGrasp& now = solved_[a];
      servo_[a]->SetSeedHints({now.q_precatch, now.q_grasp});
      reached_bMg_[a] = arm.ForwardKinematics(now.q_grasp);
      reached_bMp_[a] = arm.ForwardKinematics(now.q_precatch);
      has_reached_[a] = true;
    } else if (!has_reached_[a]) {
      reached_bMg_[a] = bMo * oMg_[a];
      reached_bMp_[a] = bMo * oMp_[a];
    }
    sequence_[a]->SetGrasp(reached_bMg_[a], reached_bMp_[a],
                           HoldingObjectInWorld() || holding_arm_ >= 0 ? t : last_found_stamp_s_,
                           switch_pending_[a]);
    switch_pending_[a] = false;
    GraspCommand command;
    const GraspPhase phase_before = sequence_[a]->phase();
    sequence_[a]->Step(q_[a], t, dt_s_, &command);
    if (world_ && phase_before != GraspPhase::kClose && command.phase == GraspPhase::kClose)
      LogClosing(a, dMo);
    if (world_ && phase_before == GraspPhase::kClose && command.phase == GraspPhase::kDone)
      LogClosed(a);
    if (command.servo_status != last_status_[a]) {
      Log(t, fmt::format("servo   {} arm: {} (phase {}, {:.1f} mm from the target)", kArmNames[a],
                         ServoStatusName(command.servo_status), GraspPhaseName(command.phase),
                         1e3 * command.joints.position_error_m));
      last_status_[a] = command.servo_status;
    }
    if (command.servo_status == ServoStatus::kInvalidState) {
      Emergency(fmt::format("{} arm: invalid joint readings", kArmNames[a]));
      return;
    }
    hw_->arms().SetJointTargets(side, command.joints.q_target_rad);
    hw_->arms().SetGripper(side, command.gripper);
  }
}

void Mission::Retract() {
  const double t = Now();
  bool home = true;
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const ArmModel& arm = hw_->platform().arm(side);
    servo_[a]->SetTarget(arm.ForwardKinematics(hw_->platform().home(side)), t);
    ServoCommand command;
    const ServoStatus status = servo_[a]->Step(q_[a], t, dt_s_, &command);
    if (status == ServoStatus::kInvalidState) {
      Emergency(fmt::format("{} arm: invalid joint readings", kArmNames[a]));
      return;
    }
    hw_->arms().SetJointTargets(side, command.q_target_rad);
    home = home && command.position_error_m < kHomeToleranceM;
  }
  if (home) {
    retracting_ = false;
    arms_.Hold(t, "home, out of the camera's view");
  }
}

void Mission::LogClosing(int a, const Eigen::Isometry3d& dMo_est) {
  // Simulation only: where the gripper closes against its grasp on the true
  // object (the truth taken in its symmetric equivalent nearest the estimate).
  const Side side = kSides[a];
  Eigen::Isometry3d dMo_true = world_->wMd().inverse() * world_->wMo();
  const ObjectSymmetry& symmetry = tracker_->model().symmetry;
  dMo_true.linear() = ClosestSymmetricRotation(dMo_true.linear(), dMo_est.linear(), symmetry);
  const Eigen::Isometry3d dMb = hw_->platform().dMb(side);
  const Eigen::Vector3d tool_d = dMe(a).translation();
  const Eigen::Vector3d target_o = (dMo_est.inverse() * dMb * reached_bMg_[a]).translation();
  const Eigen::Vector3d error_o =
      dMo_est.linear().transpose() * (dMo_est.translation() - dMo_true.translation());
  Log(Now(),
      fmt::format(
          "servo   {} arm closes: the tool is {:.1f} mm from its target and {:.1f} mm from the "
          "grasp "
          "on the true object (target at [{:.3f}, {:.3f}, {:.3f}] m in o; estimate off by {:.1f} "
          "mm "
          "([{:.1f}, {:.1f}, {:.1f}] mm in o), {:.1f} deg; {}; target solved {:.0f} ms before)",
          kArmNames[a], 1e3 * (tool_d - dMo_est * target_o).norm(),
          1e3 * (tool_d - dMo_true * target_o).norm(), target_o.x(), target_o.y(), target_o.z(),
          1e3 * (dMo_est.translation() - dMo_true.translation()).norm(), 1e3 * error_o.x(),
          1e3 * error_o.y(), 1e3 * error_o.z(),
          SymmetricRotationError(dMo_est.linear(), dMo_true.linear(), symmetry) * 180.0 / M_PI,
          HoldingObjectInWorld() ? "object held in the world" : "object seen",
          1e3 * (Now() - reached_stamp_s_[a])));
}

void Mission::LogClosed(int a) {
  const Side side = kSides[a];
  const Eigen::Isometry3d oMe = world_->wMo().inverse() * world_->wMe(side);
  const GripperState g = world_->gripper(side);
  const Eigen::Vector3d p = 1e3 * oMe.translation(), x = oMe.linear().col(0),
                        z = oMe.linear().col(2);
  Log(Now(), fmt::format("servo   {} gripper closed: {} at {:.0f} mm; the tool at [{:.1f}, {:.1f}, "
                         "{:.1f}] mm in the "
                         "true o, closing along [{:.2f}, {:.2f}, {:.2f}], approaching along "
                         "[{:.2f}, {:.2f}, {:.2f}]",
                         kArmNames[a], g.holding ? "holds" : "empty", 1e3 * g.aperture_m, p.x(),
                         p.y(), p.z(), x.x(), x.y(), x.z(), z.x(), z.y(), z.z()));
}

void Mission::Safety() {
  for (int a = 0; a < 2; ++a) {
    const Eigen::VectorXd q = world_ ? world_->arm(kSides[a]).q_true_rad() : q_[a];
    const bool inside = collision_->ArmInSafeVolume(kSides[a], q, 0.0);
    if (inside && !in_safe_volume_[a]) {
      ++result_.safe_volume_entries;
      Emergency(fmt::format("{} arm entered the safe volume", kArmNames[a]));
    }
    in_safe_volume_[a] = inside;
  }
}

// ---- The loop ------------------------------------------------------------------------------

MissionResult Mission::Run() {
  const WallClock::time_point wall_start = WallClock::now();
  t0_wall_s_ = std::chrono::duration<double>(wall_start.time_since_epoch()).count();
  global_.Start(Now());
  double stop_at_s = -1.0;
  while (true) {
    try {
      Tick();
      for (int a = 0; a < 2; ++a) q_[a] = hw_->arms().JointPositions(kSides[a]);
      Safety();
      Perception();
      Vehicle();
      Planner();
      Reevaluate();
      Servo();
    } catch (const std::exception& e) {
      Emergency(std::string("stopped on an error: ") + e.what());
    }
    const double t = Now();
    if (global_.state() == GlobalState::kDone) break;
    if (global_.state() == GlobalState::kAborted) {
      if (stop_at_s < 0) stop_at_s = t + 1.0;  // a second of the safe state in the logs
      if (t >= stop_at_s) break;
    }
    if (t > config_.timeout_s && global_.state() != GlobalState::kAborted) {
      Emergency(fmt::format("the mission took longer than {:.0f} s", config_.timeout_s));
    }
  }
  if (perceiving_.valid()) perceiving_.wait();
  if (reevaluating_.valid()) reevaluating_.wait();

  result_.sim_time_s = Now();
  result_.wall_time_s = std::chrono::duration<double>(WallClock::now() - wall_start).count();
  result_.realtime_factor =
      result_.wall_time_s > 0 ? result_.sim_time_s / result_.wall_time_s : 0.0;
  if (truth_frames_ > 0) {
    result_.pose_rmse_m = std::sqrt(sq_position_ / truth_frames_);
    result_.rotation_rmse_deg = std::sqrt(sq_rotation_ / truth_frames_);
  }
  result_.perception_ms_median = Percentile(perception_ms_, 0.5);
  result_.render_ms_median = Percentile(render_ms_, 0.5);
  const bool held =
      world_ ? world_->held_by(Side::kLeft) && world_->held_by(Side::kRight) : holding_;
  result_.success = global_.state() == GlobalState::kDone && !global_.failed() && held;
  if (!result_.success) {
    result_.failure = global_.failed() ? global_.failure()
                      : !held          ? "landed without the object held by both grippers"
                                       : "the mission did not finish";
  }
  Log(Now(), result_.success ? "mission succeeded" : "mission failed: " + result_.failure);
  return result_;
}

}  // namespace

MissionResult RunMission(const MissionOptions& options, MissionRecord* record, std::ostream* log) {
  Mission mission(options, record, log);
  return mission.Run();
}

}  // namespace aerograsp
