#include "app/commands/bench_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <thread>
#include <vector>

#include "app/calibration/interrupt_guard.h"
#include "app/calibration/tag_board_mesh.h"
#include "app/cli_checks.h"
#include "app/commands/bench_report.h"
#include "app/commands/bench_stand.h"
#include "app/commands/replay_command.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "app/runtime/mission_arms.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_record.h"
#include "app/runtime/mission_startup.h"
#include "app/runtime/telemetry_frames.h"
#include "calib/tag_board.h"
#include "core/collision.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "core/transforms.h"
#include "detection/object_tracker.h"
#include "grasp/planner.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "mission/grasp_policy.h"
#include "servo/arm_servo.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / M_PI;
// The model's points within this of the board's plane lie under its print, m
// (the board lies on the surface; the nearest other surfaces are centimetres away).
constexpr double kBoardCoversDepthM = 0.003;
constexpr double kMaxTagReprojectionPx = 1.0;  // a board pose above this is not used (as calibrate)
// A board pose from fewer tags is not used: from one 36 mm tag (the grippers
// hide the others) its rotation was 4.1 deg RMS off the truth, from two 0.5, from three 0.4.
constexpr int kMinBoardTags = 2;
constexpr double kTrackingWithinM =
    0.01;  // an arm tracks its target from the first cycle this close

/// The bench's time: the simulated world's when the camera sees it (each step
/// advances the world, deterministic), else the steady clock (each step
/// sleeps to the next period; a simulated world behind other devices
/// advances with it; real drivers run their own threads).
class BenchClock {
 public:
  BenchClock(Hardware* hw, bool simulated_camera) : hw_(hw), simulated_(simulated_camera) {
    if (!hw_->world()) hw_->StartDriverThreads();
    t0_s_ = SteadySeconds();
  }
  double now_s() const { return simulated_ ? hw_->world()->now_s() : SteadySeconds() - t0_s_; }
  void Step(double dt_s) {
    if (hw_->world()) hw_->StepSimulation(dt_s);
    if (simulated_) return;
    const double next_s = (std::floor(now_s() / dt_s) + 1.0) * dt_s;
    std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.0, next_s - now_s())));
  }

 private:
  Hardware* hw_;
  bool simulated_;
  double t0_s_ = 0.0;
};

}  // namespace

void RunBenchCommand(const BenchCommandOptions& options, std::ostream& out,
                     std::ostream& progress) {
  const std::string cli = "command line";
  if (options.out_dir.empty()) throw ConfigError("--out: an output folder is required");
  CheckRange(cli, "--frames", options.frames, 1, 100000, "");
  CheckRange(cli, "--hover-m", options.hover_m, 0.0, 0.3, "m");
  CheckRange(cli, "--path-period", options.path_period_s, 1.0, 1000.0, "s");
  CheckRange(cli, "--path-scale", options.path_scale, 0.0, 3.0, "");
  if (options.oMt && !IsValidTransform(*options.oMt)) {
    throw ConfigError(
        "--board-pose: not a rigid transform (a unit quaternion and a finite position are needed)");
  }
  MissionConfig mission = LoadMissionConfig(options.mission_config);
  // The mission's perception file unless one is given: the bench tests what the mission flies.
  if (!options.perception_config.empty()) mission.perception = options.perception_config;
  // Grasps as the mission plans them; the pre-catch pose, which the planner
  // checks for reach, is the hover point.
  const bool hover = options.hover_m > 0.0;
  if (hover) mission.planner.precatch_distance_m = options.hover_m;

  HardwareConfig hw_config;
  if (options.hardware_path.empty()) {
    hw_config = HardwareConfig::InProcessSimulation(DataPath("config/platform_4dof.yaml"),
                                                    options.world_config.empty()
                                                        ? DataPath("config/world_default.yaml")
                                                        : options.world_config);
  } else {
    hw_config = HardwareConfig::Load(options.hardware_path);
    if (!options.world_config.empty()) hw_config.world = options.world_config;
  }
  CheckBenchHardware(hw_config);
  // Without a hardware file the bench moves the object by script in the
  // in-process simulator; with one, the object is moved by hand (in a
  // simulated world, as that world's file moves it) and never placed here.
  const bool scripted = options.hardware_path.empty();
  if (!scripted && options.oMt) {
    throw ConfigError(
        fmt::format("--board-pose: with --hardware the board's place is the hardware file's "
                    "bench.board_on_object_xyz_m / _rpy_deg ({})",
                    options.hardware_path));
  }
  BenchRig rig;  // read before any device opens
  if (!scripted) rig = BenchRig::Load(options.hardware_path);
  // The test stand: the vehicle hovers in place with no sway, tilt, gusts or drift.
  const auto on_stand = [&](WorldConfig* w) {
    if (!options.object.empty()) w->object.name = options.object;
    if (scripted) w->object.motion = "static";
    w->vehicle.start = "hover";
    w->vehicle.sway_amplitude_m.setZero();
    w->vehicle.tilt_amplitude_rad = 0.0;
    w->vehicle.gust_rate_hz = 0.0;
    w->vehicle.drift_std_m = 0.0;
  };
  std::unique_ptr<Hardware> hw = Hardware::Open(hw_config, options.seed, on_stand);
  World* world = hw->world();
  // The world the camera sees (its clock, its truth), when the camera is simulated.
  World* seen = hw_config.camera.backend == "sim" ? world : nullptr;
  const Platform& platform = hw->platform();
  const ObjectModel object = LoadMissionObject(options.object, world);

  const TagBoardConfig& board = rig.board;
  const Eigen::Isometry3d oMt = options.oMt ? *options.oMt
                                : rig.oMt   ? *rig.oMt
                                            : DefaultBoardOnObject(object.mesh_o);
  // The simulated rig: the board on the object where the file (or the option) says.
  if (seen) seen->AttachToObject(MakeBoardRenderMesh(board), oMt);
  TagDetector tag_detector(board.family);

  const std::unique_ptr<ObjectTracker> tracker = MakeMissionTracker(object, mission);
  // The board's print covers the object's surface under it: the mesh's colours
  // there are not what the camera sees (on the crawler's top, 15 % of its
  // visible points), so perception compares only the shape there.
  const Eigen::Vector2d board_half_m = 0.5 * board.Size();
  tracker->ForgetColorsInBox(
      oMt, Eigen::Vector3d(board_half_m.x(), board_half_m.y(), kBoardCoversDepthM));
  const ObjectSymmetry& symmetry = tracker->model().symmetry;
  const std::unique_ptr<GraspPlanner> planner = MakeMissionPlanner(platform, object, mission);
  // The servo and grasp sequence of the mission's config.
  const PlatformCollision collision(platform);
  Eigen::VectorXd q[2];
  std::unique_ptr<ArmServo> servo[2];
  std::unique_ptr<GraspSequence> sequence[2];
  for (int a = 0; a < 2; ++a) {
    q[a] = hw->arms().JointPositions(kSides[a]);
    ArmController c = MakeArmController(mission, platform, kSides[a], collision, &q[1 - a],
                                        mission.planner.precatch_distance_m);
    servo[a] = std::move(c.servo);
    sequence[a] = std::move(c.sequence);
    sequence[a]->HoldAtPreCatch(
        hover);  // hover: stay at the pre-catch pose; else move in (the gripper stays open)
  }

  ReportFolder folder(options.out_dir, options.overwrite);
  CommandTelemetry telemetry =
      OpenTelemetry(LoadTelemetryConfig(options.telemetry), folder.path(), "bench",
                    [&out](const std::string& line) { out << "telemetry: " << line << "\n"; });
  TelemetrySink* sink = telemetry.sink();
  if (sink) sink->StaticTransforms(0.0, PlatformStaticFrames(platform));
  const std::string csv_path = (fs::path(folder.path()) / "frames.csv").string();
  std::ofstream csv(csv_path);
  if (!csv) throw std::runtime_error(csv_path + ": cannot be written");
  csv << "frame,t_s,tags_ok,tags_used,tag_reprojection_px,found,tags_tx_m,tags_ty_m,tags_tz_m,est_"
         "tx_m,est_ty_m,"
         "est_tz_m,err_translation_m,err_rotation_deg,tags_truth_translation_m,tags_truth_rotation_"
         "deg,"
         "left_servo_error_m,right_servo_error_m\n";

  // Fixed on the stand; a real stand stands level.
  const Eigen::Isometry3d wMd = seen ? seen->wMd() : Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d& dMc = platform.dMc();
  const double dt_s = 1.0 / mission.servo_rate_hz;
  const double frame_period_s =
      1.0 / (seen ? seen->config().camera.frame_rate_hz : hw_config.camera.fps);
  BenchClock clock(hw.get(), seen != nullptr);
  const double t_start = clock.now_s();
  const Eigen::Vector3d centre_o = PlacementCentre(object.mesh_o);
  auto place_object = [&](double t_s) {
    if (!scripted) return;
    world->PlaceObject(wMd * ScriptedDmo(t_s - t_start, options.path_period_s, options.path_scale,
                                         mission.grasp_dto_m, centre_o));
  };

  BenchResults run;
  run.tags_trace.name = "tags";
  run.est_trace.name = "perception";
  run.record.object_name = object.name;
  for (int a = 0; a < 2; ++a) run.record.joint_names[a] = platform.arm(kSides[a]).joint_names();

  std::optional<ObjectEstimate> estimate;  // the last found one
  SwitchState choice;
  bool has_grasp = false;
  int pair[2] = {-1, -1};  // the followed dual grasp's contact pair per arm
  // The followed pair solved again each cycle where the object is (as the
  // mission does): the tool at the grasp and at the pre-catch (hover) pose,
  // in the arm base, with the joints they were solved for.
  Eigen::Isometry3d reached_bMg[2], reached_bMp[2];
  Eigen::VectorXd reached_q[2];
  double reached_t[2] = {0.0, 0.0};
  bool tracking[2] = {false, false};
  Eigen::VectorXd q_command[2] = {q[0], q[1]};
  double next_frame_s = t_start, next_plan_s = t_start;
  int frame = 0;
  Progress bar(progress, "bench", options.frames, "frames");
  RgbdFrame rgbd;
  place_object(t_start);
  const InterruptGuard interrupt;
  std::string stopped;
  while (frame < options.frames) {
    if (InterruptGuard::Interrupted()) {
      hw->arms().Stop();
      stopped =
          fmt::format("stopped (Ctrl-C) after {} frames; the arms hold where they are", frame);
      break;
    }
    const double t = clock.now_s();
    for (int a = 0; a < 2; ++a) q[a] = hw->arms().JointPositions(kSides[a]);

    if (t + 1e-9 >= next_frame_s) {
      next_frame_s += frame_period_s;
      if (!hw->camera().Grab(&rgbd)) throw HardwareError("camera: the stream ended");
      const CameraIntrinsics& K = hw->camera().intrinsics();
      // The tags' independent pose of the object.
      const BoardPose board_pose = EstimateBoardPose(tag_detector.Detect(rgbd.color), board, K);
      const bool tags_ok = board_pose.valid && board_pose.tags_used >= kMinBoardTags &&
                           board_pose.reprojection_rms_px <= kMaxTagReprojectionPx;
      const Eigen::Isometry3d cMo_tags = board_pose.cMt * oMt.inverse();
      // Our perception, as in replay and the mission (the filter in the camera frame: the camera
      // stands still).
      const FrameReport r =
          tracker->Process(rgbd.color, rgbd.depth, rgbd.stamp_s, K, hw->camera().depth_scale_m());
      run.frame_ms.push_back(r.times.total_ms);
      const bool found = r.estimate.valid && r.estimate.state == TrackState::kFound;
      if (found) estimate = r.estimate;
      // Lost (the arms come between the camera and the object): the last found
      // pose seeds the next frame, as the mission's held world pose does (the
      // camera stands still, the object moves slowly).
      if (!found && estimate) tracker->SetInitialPose(estimate->cMo);
      if (sink) {  // the filter runs in the camera frame
        PublishPerceivedFrame(sink, t - t_start, telemetry_frame::kCamera, r.estimate, found, rgbd,
                              K, hw->camera().depth_scale_m());
      }
      const Eigen::Isometry3d cMo_truth =
          seen ? seen->wMc().inverse() * seen->wMo() : Eigen::Isometry3d::Identity();
      run.tag_frames += tags_ok;
      run.found_frames += found;
      double err_t = kNaN, err_r = kNaN, tags_truth_t = kNaN, tags_truth_r = kNaN;
      if (tags_ok && found) {
        const PoseError e{
            ComparePoses(cMo_tags, r.estimate.cMo).translation_m,
            SymmetricRotationError(r.estimate.cMo.linear(), cMo_tags.linear(), symmetry)};
        run.perception_vs_tags.Add(e);
        err_t = e.translation_m, err_r = kRadToDeg * e.rotation_rad;
      }
      if (tags_ok && seen) {
        const PoseError e =
            ComparePoses(cMo_truth, cMo_tags);  // the board breaks the object's symmetry
        run.tags_vs_truth.Add(e);
        tags_truth_t = e.translation_m, tags_truth_r = kRadToDeg * e.rotation_rad;
      }
      if (found && seen) {
        run.perception_vs_truth.Add(
            {ComparePoses(cMo_truth, r.estimate.cMo).translation_m,
             SymmetricRotationError(r.estimate.cMo.linear(), cMo_truth.linear(), symmetry)});
      }
      AddBenchTrace(&run.tags_trace, t - t_start, tags_ok, cMo_tags, kNaN);
      AddBenchTrace(&run.est_trace, t - t_start, found, r.estimate.cMo, err_r);
      MissionSample sample;
      sample.t_s = t - t_start;
      sample.found = found;
      for (int a = 0; a < 2; ++a)
        sample.q_target_rad[a] = q_command[a], sample.q_actual_rad[a] = q[a];
      run.record.samples.push_back(sample);
      if (found && tags_ok && (!run.record.snapshot || frame == options.frames / 2)) {
        MissionSnapshot snap;
        snap.t_s = t - t_start;
        snap.color = rgbd.color;
        snap.K = K;
        snap.has_box = r.detection.has_value();
        if (r.detection) {
          snap.box_x0 = r.detection->box.x0, snap.box_y0 = r.detection->box.y0;
          snap.box_x1 = r.detection->box.x1, snap.box_y1 = r.detection->box.y1;
        }
        snap.has_pose = true;
        snap.cMo = r.estimate.cMo;
        run.record.snapshot = snap;
      }
      const double last_error[2] = {
          run.servo_traces[0].to_target_m.empty() ? kNaN : run.servo_traces[0].to_target_m.back(),
          run.servo_traces[1].to_target_m.empty() ? kNaN : run.servo_traces[1].to_target_m.back()};
      const Eigen::Vector3d p_tags = cMo_tags.translation(), p_est = r.estimate.cMo.translation();
      csv << fmt::format(
          "{},{:.4f},{},{},{:.3f},{},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.5f}"
          ",{:.4f},"
          "{:.5f},{:.5f}\n",
          frame, t - t_start, int(tags_ok), board_pose.tags_used, board_pose.reprojection_rms_px,
          int(found), p_tags.x(), p_tags.y(), p_tags.z(), p_est.x(), p_est.y(), p_est.z(), err_t,
          err_r, tags_truth_t, tags_truth_r, last_error[0], last_error[1]);
      ++frame;
      bar.Update(frame);
    }

    // Grasp (re-)evaluation where perception sees the object now.
    if (estimate && t + 1e-9 >= next_plan_s) {
      next_plan_s += 1.0 / mission.reevaluate_rate_hz;
      PlanQuery query;
      query.dMo = dMc * estimate->cMo;
      query.q_left = q[0];
      query.q_right = q[1];
      query.gravity_d = (wMd.linear().transpose() * Eigen::Vector3d::UnitZ()).normalized();
      const SwitchDecision decision =
          DecideSwitch(planner->Plan(query), choice, mission.policy.switch_margin);
      ++run.plans;
      if (decision.status == SwitchDecision::Status::kNoGrasp) {
        ++run.no_grasp_plans;
        has_grasp = false;
      } else {
        const bool changed = !has_grasp || decision.status == SwitchDecision::Status::kSwitch;
        run.switches += has_grasp && decision.status == SwitchDecision::Status::kSwitch;
        const ArmGrasp* grasps[2] = {&decision.grasp.left, &decision.grasp.right};
        for (int a = 0; a < 2; ++a) {
          if (changed || sequence[a]->phase() == GraspPhase::kTimedOut) {
            pair[a] = grasps[a]->pair;
            reached_q[a].resize(0);
            tracking[a] = false;
            sequence[a]->Start(t);
          }
        }
        has_grasp = true;
        if (sink && changed) sink->GraspPair({t - t_start, pair[0], pair[1], decision.reason});
      }
      choice = decision.next;
    }

    // Servo both arms to their targets on the estimated object.
    for (int a = 0; a < 2; ++a) {
      const Side side = kSides[a];
      double to_target = kNaN, to_truth = kNaN;
      if (has_grasp && estimate) {
        const Eigen::Isometry3d dMo = dMc * estimate->cMo;
        // The planner's closed-form IK for the followed pair where the object
        // is now: targets the arm reaches exactly. A solution far in joint
        // space from the last is another IK branch and is not followed (the
        // allowance grows with the time since the last one, as the object
        // moves on); out of reach, the last targets stand.
        ArmGrasp solved;
        Infeasibility why = Infeasibility::kNone;
        if (planner->EvaluateArm(side, pair[a], dMo, q[a], &solved, &why) &&
            (reached_q[a].size() == 0 ||
             OnFollowedBranch(solved.q_grasp, reached_q[a], t - reached_t[a], mission.policy))) {
          reached_q[a] = solved.q_grasp;
          reached_t[a] = t;
          reached_bMg[a] = platform.arm(side).ForwardKinematics(solved.q_grasp);
          reached_bMp[a] = platform.arm(side).ForwardKinematics(solved.q_precatch);
          servo[a]->SetSeedHints({solved.q_precatch, solved.q_grasp});
        }
      }
      if (has_grasp && estimate && reached_q[a].size() > 0) {
        const Eigen::Isometry3d bMd = platform.dMb(side).inverse();
        const Eigen::Isometry3d bMo = bMd * dMc * estimate->cMo;
        // A briefly lost object is held where it was last found (the mission
        // holds its world pose for lost_timeout_s); after that the target is stale and the arm
        // holds.
        const bool held = t - estimate->stamp_s < mission.policy.lost_timeout_s;
        sequence[a]->SetGrasp(reached_bMg[a], reached_bMp[a], held ? t : estimate->stamp_s);
        GraspCommand command;
        const GraspPhase phase = sequence[a]->Step(q[a], t, dt_s, &command);
        const ServoStatus status = command.servo_status;
        ++run.status_cycles[ServoStatusName(status)];
        q_command[a] = command.joints.q_target_rad;
        hw->arms().SetJointTargets(side, q_command[a]);
        // The pose the arm servoes to in this phase: the pre-catch (hover) pose, then the grasp.
        const Eigen::Isometry3d& bMh =
            phase == GraspPhase::kPreCatch ? reached_bMp[a] : reached_bMg[a];
        const Eigen::Vector3d p_b = platform.arm(side).ForwardKinematics(q[a]).translation();
        if (status == ServoStatus::kMoving) {
          to_target = (p_b - bMh.translation()).norm();
          // The same target relative to the object, on the true object turned
          // by the symmetry nearest the estimate (the crawler's half turns look alike).
          if (seen) {
            Eigen::Isometry3d cMo_truth = seen->wMc().inverse() * seen->wMo();
            cMo_truth.linear() =
                ClosestSymmetricRotation(cMo_truth.linear(), estimate->cMo.linear(), symmetry);
            const Eigen::Isometry3d bMh_truth = bMd * dMc * cMo_truth * bMo.inverse() * bMh;
            to_truth = (p_b - bMh_truth.translation()).norm();
          }
          tracking[a] = tracking[a] || to_target < kTrackingWithinM;
          run.servo_error_all_m.push_back(to_target);
          if (tracking[a]) {
            run.servo_error_tracking_m.push_back(to_target);
            if (seen) run.servo_error_to_truth_m.push_back(to_truth);
          }
        } else {
          tracking[a] = false;
        }
      }
      run.servo_traces[a].t_s.push_back(t - t_start);
      run.servo_traces[a].to_target_m.push_back(to_target);
      run.servo_traces[a].to_truth_m.push_back(to_truth);
    }
    if (sink) {
      sink->Arms(ArmsState(t - t_start, platform, q, hw->arms()));
      std::vector<TelemetryTransform> tf = ToolFrames(platform, q);
      tf.push_back({telemetry_frame::kWorld, telemetry_frame::kBody, wMd});
      if (estimate)
        tf.push_back({telemetry_frame::kCamera, telemetry_frame::kObject, estimate->cMo});
      sink->Transforms(t - t_start, tf);
    }
    clock.Step(dt_s);
    place_object(clock.now_s());
  }
  bar.Finish();
  const std::string mcap = telemetry.Close();
  if (!mcap.empty()) out << "Wrote " << folder.Final(mcap) << "\n";
  run.frames = frame;
  csv.close();

  BenchReportInfo info;
  info.out_dir = folder.path();
  info.object_name = object.name;
  info.object_mesh_o = object.mesh_o;
  info.hardware = hw_config.source;
  info.seed = options.seed;
  info.perception = mission.perception.empty() ? "code defaults" : mission.perception;
  info.hover_m = options.hover_m;
  info.board = board;
  info.oMt = oMt;
  WriteBenchReport(info, run, out);
  folder.Commit();  // also when stopped early or blind: the report says so
  out << "  wrote " << folder.final_path() << "/summary.json, " << folder.final_path()
      << "/index.html\n";
  if (!stopped.empty()) throw HardwareError("bench: " + stopped + "; the report covers them");

  if (run.tag_frames == 0) {
    throw std::runtime_error(fmt::format(
        "bench: the tag board was never detected in {} frames (board {}x{} tags of {:.0f} mm, ids "
        "from {}, on the "
        "object at oMt translation {:.3f} {:.3f} {:.3f} m): is its printed face towards the camera "
        "({})? "
        "See {}/frames.csv",
        frame, board.rows, board.cols, 1e3 * board.tag_size_m, board.first_id,
        oMt.translation().x(), oMt.translation().y(), oMt.translation().z(),
        scripted ? "--board-pose"
                 : "bench.board and bench.board_on_object_* in " + options.hardware_path,
        options.out_dir));
  }
  if (run.found_frames == 0) {
    throw std::runtime_error(
        fmt::format("bench: perception never found the object ({}) in {} frames; see {}/frames.csv",
                    object.name, frame, options.out_dir));
  }
}

void AddBenchOptions(CLI::App* cmd, BenchCommandOptions* o) {
  // Seven numbers on the command line, a pose in the options once parsed.
  const auto board_pose = std::make_shared<std::vector<double>>();
  cmd->add_option("--out", o->out_dir, "Report folder (index.html, summary.json, frames.csv)")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  CLI::Option* hardware =
      cmd->add_option("--hardware", o->hardware_path,
                      "Hardware YAML: the real camera and arms (the object moved by hand, the "
                      "board where its bench section says), or data/config/hardware_sim.yaml "
                      "(the real drivers against simulated devices)")
          ->check(CLI::ExistingFile);
  cmd->add_option("--world", o->world_config, "World YAML [data/config/world_default.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_option("--object", o->object, "Object: a shipped name or a model path [the world's]");
  cmd->add_option("--frames", o->frames, "Camera frames")
      ->capture_default_str()
      ->check(cli::Range(1, 100000));
  cmd->add_option("--seed", o->seed, "World seed")->capture_default_str()->check(cli::Seed());
  AddTelemetryOptions(cmd, &o->telemetry);
  cmd->add_option(
         "--hover-m", o->hover_m,
         "Servo to the grasp moved back this far along its approach (0: the grasp itself), m")
      ->capture_default_str()
      ->check(cli::Finite());
  cmd->add_option("--path-period", o->path_period_s, "Period of the object's scripted path, s")
      ->capture_default_str()
      ->excludes(hardware)
      ->check(cli::Range(1.0, 1000.0));
  cmd->add_option("--path-scale", o->path_scale,
                  "Scale of the scripted path (1: +-6 cm fore and aft; 0: the object held still "
                  "at the grasp point)")
      ->capture_default_str()
      ->excludes(hardware)
      ->check(cli::Finite());
  cmd->add_option(
         "--board-pose", *board_pose,
         "The tag board on the object, oMt: x y z (m) qw qx qy qz [centred on its top, face up]")
      ->expected(7)
      ->excludes(hardware)
      ->check(cli::Finite());
  cmd->add_option(
         "--perception", o->perception_config,
         "Perception YAML (see data/config/perception_default.yaml) [the mission config's]")
      ->check(CLI::ExistingFile);
  cmd->callback([o, board_pose] {
    if (!board_pose->empty()) o->oMt = PoseFromValues(*board_pose, "--board-pose");
  });
}

}  // namespace aerograsp
