#include "app/runtime/mission_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <thread>

#include "app/report/statistics.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_evaluator.h"
#include "app/runtime/mission_grasp.h"
#include "app/runtime/mission_health.h"
#include "app/runtime/mission_object.h"
#include "app/runtime/mission_setup.h"
#include "app/runtime/mission_startup.h"
#include "app/runtime/mission_vehicle.h"
#include "app/runtime/telemetry_frames.h"
#include "core/collision.h"
#include "core/object_model.h"
#include "core/thread_clock.h"
#include "detection/model_cloud.h"
#include "detection/object_tracker.h"
#include "grasp/placement.h"
#include "grasp/planner.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "mission/grasp_policy.h"
#include "mission/state_machines.h"

namespace aerograsp {
namespace {

using WallClock = std::chrono::steady_clock;

/// One frame's result.
struct Perceived {
  FrameReport report;
  std::shared_ptr<RgbdFrame> frame;
};

/// Everything the loop needs, built before take-off.
class Mission {
 public:
  Mission(const MissionOptions& options, MissionRecord* record, std::ostream* log,
          const MissionLinks& links);
  MissionResult Run();

 private:
  void Log(double t_s, const std::string& line, TelemetryLevel level = TelemetryLevel::kInfo);
  void OnTransition(const StateTransition& t);
  double Now() const;
  /// Advances the clock by one servo period (simulated) or waits for it (real).
  void Tick();
  void Emergency(const std::string& cause);

  void Perception();
  void HandlePerceived(Perceived p);
  void Vehicle();
  void Safety();
  /// The arms' cycle, its wall and thread CPU time kept for the result.
  void ServoCycle();
  /// An outside emergency stop requested: the mission's emergency, once.
  void PollEmergencyStop();
  /// The arms, the moving transforms and a new followed grasp pair to the telemetry.
  void PublishCycle();
  /// A device fault: logged, counted, and the arms stop and the vehicle holds.
  void DeviceFaults(const std::vector<DeviceFault>& faults);
  /// The object in the body frame now, as the robot knows it.
  Eigen::Isometry3d dMoNow() const;
  /// Arm a's tool in the body frame, at its measured joints.
  Eigen::Isometry3d dMe(int a) const;

  MissionConfig config_;
  MissionRecord* record_;
  std::ostream* log_;
  MissionLinks links_;
  MissionResult result_;

  std::unique_ptr<Hardware> hw_;
  std::unique_ptr<MissionHealth> health_;
  const World* sim_clock_ = nullptr;  // the simulated world, for its clock only
  std::unique_ptr<ObjectModel> object_;
  std::unique_ptr<ObjectTracker> tracker_;
  std::shared_ptr<const GraspPlanner> planner_;  // shared with missions of this configuration
  Eigen::Matrix3d placement_dRo_ = Eigen::Matrix3d::Identity();  // the object's, upright
  std::unique_ptr<PlatformCollision> collision_;
  Eigen::VectorXd q_[2];           // measured joints, read by the other arm's forbidden predicate
  ArmJointHistory joint_history_;  // the measured joints of the last second, for the frames
  std::unique_ptr<MissionEvaluator> evaluator_;  // simulation: compares with the truth
  std::unique_ptr<TrackedObject> object_pose_;
  std::unique_ptr<VehicleLegs> legs_;
  std::unique_ptr<GraspScheduler> grasp_;

  GlobalMachine global_;
  VehicleMachine vehicle_;
  VisionMachine vision_;
  PlannerMachine planner_sm_;
  ArmsMachine arms_;

  // Clock and rates.
  double dt_s_ = 0.01;
  double t0_wall_s_ = 0.0;
  double next_frame_s_ = 0.0, frame_period_s_ = 1.0 / 30.0;

  // Perception in flight: started at a frame, collected at the next.
  std::future<Perceived> perceiving_;
  std::vector<double> perception_ms_, render_ms_;
  int snapshot_priority_ = 0;
  bool hold_commanded_ = false;  // Emergency() has told the vehicle to hold

  // Safety, on the measured joints.
  bool in_safe_volume_[2] = {false, false};
  int safe_volume_entries_ = 0;

  // Telemetry and the outside emergency stop.
  bool outside_stop_ = false;
  SwitchState published_pair_;
  std::string planner_cause_;  // the planner machine's last transition: why the pair changed
};

Mission::Mission(const MissionOptions& options, MissionRecord* record, std::ostream* log,
                 const MissionLinks& links)
    : record_(record),
      log_(log),
      links_(links),
      global_([this](const StateTransition& t) { OnTransition(t); }),
      vehicle_([this](const StateTransition& t) { OnTransition(t); }),
      vision_([this](const StateTransition& t) { OnTransition(t); }),
      planner_sm_(1, {}),
      arms_([this](const StateTransition& t) { OnTransition(t); }) {
  config_ = LoadMissionConfig(options);
  planner_sm_ = PlannerMachine(config_.policy.max_attempts,
                               [this](const StateTransition& t) { OnTransition(t); });
  DeviceHealthLimits health;
  hw_ = OpenMissionHardware(options, config_, &health);
  health_ = std::make_unique<MissionHealth>(hw_.get(), health);
  for (int a = 0; a < 2; ++a) {  // camera-to-arm calibrations: dMb = dMc * cMb
    if (config_.calibrated_cMb[a])
      hw_->SetArmBase(kSides[a], hw_->platform().dMc() * *config_.calibrated_cMb[a]);
  }
  const World* world = hw_->world();
  sim_clock_ = world;
  if (!world) hw_->StartDriverThreads();  // else Tick() steps the drivers with the world
  const Platform& platform = hw_->platform();

  object_ = std::make_unique<ObjectModel>(LoadMissionObject(options, world));
  const std::shared_ptr<const MissionSetup> setup =
      MissionSetupFor(options, platform, *object_, config_);
  tracker_ = MakeMissionTracker(*object_, config_, setup->tracker_model);
  tracker_->SetRobot(platform);  // the arms' own pixels leave the depth
  planner_ = setup->planner;
  const std::string placement = PlaceMissionObject(*setup, &config_);
  if (!placement.empty()) Log(Now(), placement);
  placement_dRo_ = UprightDmo(config_.grasp_dto_m, config_.placement.object_yaw_rad).linear();

  collision_ = std::make_unique<PlatformCollision>(platform);
  for (int a = 0; a < 2; ++a) q_[a] = hw_->arms().JointPositions(kSides[a]);
  const auto log_now = [this](const std::string& line) { Log(Now(), line); };
  if (world) {
    evaluator_ = std::make_unique<MissionEvaluator>(*world, platform, *collision_,
                                                    tracker_->model().symmetry, log_now);
  }
  dt_s_ = 1.0 / config_.servo_rate_hz;
  if (world) frame_period_s_ = 1.0 / world->config().camera.frame_rate_hz;
  object_pose_ = std::make_unique<TrackedObject>(
      config_, tracker_->model().symmetry,
      Eigen::AlignedBox3d(object_->mesh_o.BoundsMin(), object_->mesh_o.BoundsMax()),
      frame_period_s_, [this](int a) { return dMe(a); }, log_now);
  legs_ = std::make_unique<VehicleLegs>(
      config_, health_->autopilot(), &global_, &vehicle_,
      [this](const std::string& cause) { Emergency(cause); }, log_now);
  const auto emergency = [this](const std::string& cause) { Emergency(cause); };
  grasp_ = std::make_unique<GraspScheduler>(
      config_, platform, *planner_, *collision_, q_, object_pose_.get(),
      GraspMachines{&global_, &vision_, &planner_sm_, &arms_}, &hw_->arms(), evaluator_.get(),
      &result_, record_, [this] { return dMoNow(); }, emergency, log_now);
  if (record_) {
    record_->object_name = object_->name;
    record_->object_mesh_o = object_->mesh_o;
    for (int a = 0; a < 2; ++a) record_->joint_names[a] = platform.arm(kSides[a]).joint_names();
  }
}

double Mission::Now() const {
  if (sim_clock_) return sim_clock_->now_s();
  return std::chrono::duration<double>(WallClock::now().time_since_epoch()).count() - t0_wall_s_;
}

void Mission::Tick() {
  if (sim_clock_) {
    hw_->StepSimulation(dt_s_);
    return;
  }
  const double next = (std::floor(Now() / dt_s_) + 1.0) * dt_s_;
  std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.0, next - Now())));
}

void Mission::Log(double t_s, const std::string& line, TelemetryLevel level) {
  if (log_) *log_ << fmt::format("[{:8.3f} s] {}\n", t_s, line);
  if (links_.telemetry) links_.telemetry->Log(t_s, level, "mission", line);
}

void Mission::OnTransition(const StateTransition& t) {
  if (log_) {
    *log_ << fmt::format("[{:8.3f} s] {:<7} {} -> {}: {}\n", t.t_s, t.machine, t.from, t.to,
                         t.cause);
  }
  if (record_) record_->transitions.push_back({t.t_s, t.machine, t.from, t.to, t.cause});
  if (t.machine == "planner") planner_cause_ = t.cause;
  if (links_.telemetry) links_.telemetry->Transition({t.t_s, t.machine, t.from, t.to, t.cause});
}

void Mission::Emergency(const std::string& cause) {
  const double t = Now();
  // Counted once: the stop is latched, later causes find the arms stopped.
  if (arms_.EmergencyStop(t, cause)) ++result_.emergency_stops;
  global_.Emergency(t, cause);
  try {
    hw_->arms().Stop();
  } catch (const std::exception& e) {
    Log(t, std::string("arms stop failed: ") + e.what());
  }
  // The vehicle is told to hold once: a refused or unanswered hold is logged,
  // not resent by every later cause (on a lost link each try blocks for the
  // command's timeouts; the autopilot's own failsafe takes over).
  if (hold_commanded_) return;
  hold_commanded_ = true;
  try {
    const CommandAck ack = hw_->autopilot().Hold();
    if (!ack.accepted) Log(t, "autopilot refused hold: " + ack.reason);
  } catch (const std::exception& e) {
    Log(t, std::string("autopilot hold failed: ") + e.what());
  }
}

Eigen::Isometry3d Mission::dMe(int a) const {
  const Side side = kSides[a];
  return hw_->platform().dMb(side) * hw_->platform().arm(side).ForwardKinematics(q_[a]);
}

Eigen::Isometry3d Mission::dMoNow() const {
  // A symmetric object as its twin nearest the placement's orientation: its
  // contact pairs then lie where the placement was searched (a pipe's turn
  // about its own axis is not seen, and any estimate of it is as good).
  const Eigen::Isometry3d dMo = object_pose_->dMo(Now(), hw_->autopilot().State().wMd);
  const ObjectSymmetry& symmetry = tracker_->model().symmetry;
  return WithSymmetricRotation(
      dMo, ClosestSymmetricRotation(dMo.linear(), placement_dRo_, symmetry), symmetry);
}

// ---- Perception ---------------------------------------------------------------

void Mission::Perception() {
  const double t = Now();
  joint_history_.Add(t, {q_[0], q_[1]});
  if (t + 1e-9 < next_frame_s_) return;
  next_frame_s_ += frame_period_s_;
  if (next_frame_s_ < t) next_frame_s_ = t + frame_period_s_;
  // Vision runs while the vehicle flies (the camera sees only the pad before),
  // nor once both grippers hold the object: nothing steers by it any more.
  auto wanted = [this] {
    const VehicleMode mode = vehicle_.state();
    return mode != VehicleMode::kIdle && mode != VehicleMode::kTakeOff &&
           global_.state() != GlobalState::kDone && global_.state() != GlobalState::kAborted &&
           !grasp_->holding();
  };
  // The frame is rendered while the tracker still works on the previous one
  // (the two take about as long); its result is handled at this frame's time.
  std::shared_ptr<RgbdFrame> frame;
  Eigen::Isometry3d wMd = Eigen::Isometry3d::Identity();  // the vehicle when the frame was taken
  if (wanted()) {
    frame = std::make_shared<RgbdFrame>();
    const WallClock::time_point render_start = WallClock::now();
    if (!hw_->camera().Grab(frame.get())) throw HardwareError("camera: the stream ended");
    render_ms_.push_back(
        std::chrono::duration<double, std::milli>(WallClock::now() - render_start).count());
    DeviceFaults(health_->Frame(t, *frame));
    wMd = hw_->autopilot().State().wMd;
    if (evaluator_) evaluator_->FrameTaken(frame->stamp_s);
  }
  if (!frame) health_->CameraIdle();
  if (perceiving_.valid()) HandlePerceived(perceiving_.get());
  if (!frame || !wanted()) return;
  const CameraIntrinsics K = hw_->camera().intrinsics();
  const double scale = hw_->camera().depth_scale_m();
  // Briefly lost with the object held at its last world pose: that pose seeds
  // the tracker (a local ICP) instead of a global registration on the frame,
  // which costs ten times more and may lock onto clutter.
  if (object_pose_->HeldInWorld(t))
    tracker_->SetInitialPose(hw_->platform().dMc().inverse() * dMoNow());
  ObjectTracker* tracker = tracker_.get();
  const Eigen::Isometry3d wMc = wMd * hw_->platform().dMc();
  const std::optional<ArmJointPositions> q_frame = joint_history_.At(frame->stamp_s);
  perceiving_ = std::async(std::launch::async, [tracker, K, scale, wMc, q_frame, frame] {
    Perceived p;
    p.frame = frame;
    p.report = tracker->Process(frame->color, frame->depth, frame->stamp_s, K, scale, wMc, q_frame);
    return p;
  });
}

void Mission::HandlePerceived(Perceived p) {
  const double t = Now();
  ++result_.frames;
  result_.global_registrations += p.report.global_init ? 1 : 0;
  perception_ms_.push_back(p.report.times.total_ms);
  const ObjectEstimate& estimate = p.report.estimate;
  const bool found = estimate.valid && estimate.state == TrackState::kFound;
  const VisionSignal signal =
      vision_.Update(t, found,
                     found ? fmt::format("pose found (confidence {:.2f})", estimate.confidence)
                           : fmt::format("pose lost (confidence {:.2f})", estimate.confidence));
  const Eigen::Isometry3d dMc = hw_->platform().dMc();
  object_pose_->Update(t, estimate, dMc);
  if (signal == VisionSignal::kLost) vehicle_.Lost(t);

  MissionSample s;
  s.t_s = p.frame->stamp_s;
  s.estimate_valid = estimate.valid;
  s.found = found;
  if (estimate.valid) s.dto_estimate_m = (dMc * estimate.cMo).translation();
  for (int a = 0; a < 2; ++a) s.q_actual_rad[a] = s.q_target_rad[a] = q_[a];
  if (evaluator_) {
    evaluator_->FramePerceived(p.frame->stamp_s, estimate.valid, estimate.cMo,
                               found && global_.state() == GlobalState::kGrasping, &s);
  }
  s.vehicle_w_m = hw_->autopilot().State().wMd.translation();
  if (links_.telemetry) {  // the tracker's filter runs in w: it is given wMc
    PublishPerceivedFrame(links_.telemetry, p.frame->stamp_s, telemetry_frame::kWorld, estimate,
                          found, *p.frame, hw_->camera().intrinsics(),
                          hw_->camera().depth_scale_m());
  }
  if (!record_) return;
  record_->samples.push_back(s);
  // The report's camera frame: the last one before the grippers close with the
  // arms servoing, else the last with the object found.
  const int priority = !found ? 0 : grasp_->active() ? 2 : 1;
  if (priority > 0 && priority >= snapshot_priority_ && !grasp_->holding()) {
    snapshot_priority_ = priority;
    record_->snapshot =
        FrameSnapshot(p.frame->stamp_s, p.frame->color, hw_->camera().intrinsics(), p.report);
  }
}

// ---- Vehicle -----------------------------------------------------------------------

void Mission::Vehicle() {
  const double t = Now();
  VehicleView view;
  view.object_found = vision_.state() == VisionState::kFound;
  view.lost_for_s = object_pose_->lost_for_s(t);
  view.one_gripper_carries = object_pose_->holder() >= 0;
  view.a_gripper_holds = grasp_->a_gripper_holds();
  view.have_object_w = object_pose_->have_world_pose();
  view.object_w_m = object_pose_->object_w_filtered();
  if (view.object_found) view.object_v_w_mps = object_pose_->estimate().v_f;
  if (!legs_->Step(t, view)) return;
  const bool idle = planner_sm_.state() == PlannerState::kIdle;
  if (idle && view.object_found &&
      ShouldPlan(idle, view.object_found, (dMoNow().translation() - config_.grasp_dto_m).norm(),
                 config_.policy)) {
    planner_sm_.Start(t);
  }
}

// ---- Safety, on the measured joints ---------------------------------------------------

void Mission::Safety() {
  for (int a = 0; a < 2; ++a) {
    const bool inside = collision_->ArmInSafeVolume(kSides[a], q_[a], 0.0);
    if (inside && !in_safe_volume_[a]) {
      ++safe_volume_entries_;
      Emergency(fmt::format("{} arm entered the safe volume", kArmNames[a]));
    }
    in_safe_volume_[a] = inside;
  }
}

void Mission::ServoCycle() {
  const WallClock::time_point wall_start = WallClock::now();
  const double cpu_start_ms = ThreadCpuMs();
  grasp_->Plan(Now());
  grasp_->Reevaluate(Now());
  grasp_->Servo(Now(), dt_s_);
  const double cpu_ms = ThreadCpuMs() - cpu_start_ms;
  const double wall_ms =
      std::chrono::duration<double, std::milli>(WallClock::now() - wall_start).count();
  result_.servo_step_ms_max = std::max(result_.servo_step_ms_max, wall_ms);
  result_.servo_step_cpu_ms_max = std::max(result_.servo_step_cpu_ms_max, cpu_ms);
}

// ---- Telemetry and the outside emergency stop ----------------------------------------

void Mission::PollEmergencyStop() {
  const EmergencyStopPoll poll = links_.emergency_stop->Poll(Now());
  for (const std::string& note : poll.notes) Log(Now(), note, TelemetryLevel::kWarn);
  if (!poll.stop || outside_stop_) return;
  outside_stop_ = true;
  Log(Now(), "emergency stop requested by " + poll.source, TelemetryLevel::kError);
  Emergency(fmt::format("emergency stop from {}{}", poll.source,
                        poll.reason.empty() ? "" : ": " + poll.reason));
}

void Mission::PublishCycle() {
  TelemetrySink* sink = links_.telemetry;
  const double t = Now();
  const Platform& platform = hw_->platform();
  sink->Arms(ArmsState(t, platform, q_, hw_->arms()));
  const Eigen::Isometry3d wMd = hw_->autopilot().State().wMd;
  std::vector<TelemetryTransform> tf = ToolFrames(platform, q_);
  tf.push_back({telemetry_frame::kWorld, telemetry_frame::kBody, wMd});
  if (object_pose_->have_world_pose() || object_pose_->holder() >= 0)
    tf.push_back({telemetry_frame::kWorld, telemetry_frame::kObject, wMd * dMoNow()});
  sink->Transforms(t, tf);
  const SwitchState& followed = grasp_->followed();
  if (followed.left_pair != published_pair_.left_pair ||
      followed.right_pair != published_pair_.right_pair) {
    published_pair_ = followed;
    sink->GraspPair({t, followed.left_pair, followed.right_pair, planner_cause_});
  }
}

void Mission::DeviceFaults(const std::vector<DeviceFault>& faults) {
  for (const DeviceFault& f : faults) {
    Log(Now(), "device fault: " + f.Text(), TelemetryLevel::kError);
    Emergency(f.Text());
  }
}

// ---- The loop ------------------------------------------------------------------------------

MissionResult Mission::Run() {
  const WallClock::time_point wall_start = WallClock::now();
  const double cpu_start_ms = ProcessCpuMs();
  t0_wall_s_ = std::chrono::duration<double>(wall_start.time_since_epoch()).count();
  if (links_.telemetry)
    links_.telemetry->StaticTransforms(Now(), PlatformStaticFrames(hw_->platform()));
  global_.Start(Now());
  double stop_at_s = -1.0;
  while (true) {
    try {
      Tick();
      for (int a = 0; a < 2; ++a) q_[a] = hw_->arms().JointPositions(kSides[a]);
      if (links_.emergency_stop) PollEmergencyStop();
      DeviceFaults(health_->Poll(Now()));
      if (evaluator_) evaluator_->Step();
      Safety();
      Perception();
      Vehicle();
      grasp_->AwaitDue(Now());
      ServoCycle();
      if (links_.telemetry) PublishCycle();
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
  grasp_->Wait();

  result_.sim_time_s = Now();
  result_.wall_time_s = std::chrono::duration<double>(WallClock::now() - wall_start).count();
  result_.realtime_factor =
      result_.wall_time_s > 0 ? result_.sim_time_s / result_.wall_time_s : 0.0;
  result_.cpu_time_s = 1e-3 * (ProcessCpuMs() - cpu_start_ms);
  result_.realtime_factor_cpu =
      result_.cpu_time_s > 0 ? result_.sim_time_s / result_.cpu_time_s : 0.0;
  result_.perception_ms_median = Percentile(perception_ms_, 0.5);
  result_.render_ms_median = Percentile(render_ms_, 0.5);
  // The truth figures come from the evaluator in simulation; on hardware the
  // robot's own readings are all there is.
  result_.safe_volume_entries =
      evaluator_ ? evaluator_->safe_volume_entries() : safe_volume_entries_;
  result_.device_faults = health_->counts();
  result_.simulated_fault_s = hw_->FirstSimulatedFaultS();
  if (evaluator_) {
    result_.pose_rmse_m = evaluator_->pose_rmse_m();
    result_.rotation_rmse_deg = evaluator_->rotation_rmse_deg();
    result_.grasp_frames = evaluator_->grasp_frames();
    result_.arm_contacts = evaluator_->arm_contacts();
    result_.closes = evaluator_->closes();
  }
  const bool held = evaluator_ ? evaluator_->both_hold() : grasp_->holding();
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

MissionResult RunMission(const MissionOptions& options, MissionRecord* record, std::ostream* log,
                         const MissionLinks& links) {
  Mission mission(options, record, log, links);
  return mission.Run();
}

}  // namespace aerograsp
