#include "app/commands/bench_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "app/calibration/tag_board_mesh.h"
#include "app/report/mission_plots.h"
#include "app/report/plot_panel.h"
#include "app/report/pose_plot.h"
#include "app/report/progress.h"
#include "app/report/report_html.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "app/runtime/mission_arms.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_record.h"
#include "calib/tag_board.h"
#include "core/collision.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/mesh.h"
#include "core/transforms.h"
#include "detection/object_tracker.h"
#include "detection/perception_config.h"
#include "grasp/contacts.h"
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
constexpr Side kSides[2] = {Side::kLeft, Side::kRight};
constexpr double kMaxTagReprojectionPx = 1.0;  // a board pose above this is not used (as calibrate)
// A board pose from fewer tags is not used: from one 36 mm tag (the grippers
// hide the others) its rotation was 4.1 deg RMS off the truth, from two 0.5, from three 0.4.
constexpr int kMinBoardTags = 2;
constexpr double kTrackingWithinM =
    0.01;  // an arm tracks its target from the first cycle this close
constexpr double kBoardAboveSurfaceM = 0.0005;  // the printed board lies this far above the face

/// The bench's board: one row of three 36 mm tags (44 x 132 mm), which fits
/// the crawler's 60 mm recess between its tracks and resolves at 0.5 m.
TagBoardConfig BenchBoard() {
  TagBoardConfig board;
  board.rows = 1;
  board.cols = 3;
  board.tag_size_m = 0.036;
  board.spacing_m = 0.008;
  board.margin_m = 0.004;
  board.first_id = 20;
  return board;
}

/// Where a ray down the z axis of o first meets the mesh (its top over the origin), m along z_o.
double TopSurfaceAtCentre(const TriangleMesh& mesh_o) {
  const double above_m = mesh_o.BoundsMax().z() + 1.0;
  const std::vector<double> hits =
      IntersectRay(mesh_o, Eigen::Vector3d(0.0, 0.0, above_m), -Eigen::Vector3d::UnitZ());
  return hits.empty() ? mesh_o.BoundsMax().z() : above_m - hits.front();
}

/// The board centred on the object's top, printed face up (+z_o; t's z points
/// into the board, so z_t = -z_o), x_t along x_o.
Eigen::Isometry3d DefaultBoardOnObject(const TriangleMesh& mesh_o) {
  return MakeTransform(Eigen::Vector3d(0.0, 0.0, TopSurfaceAtCentre(mesh_o) + kBoardAboveSurfaceM),
                       Eigen::Vector3d(M_PI, 0.0, 0.0));
}

/// The scripted path of the object in the body frame d: upright (z_o up, x_o
/// across the vehicle along y_d, as on the mission's pipe), around the
/// mission's grasp point grasp_dto_m. At scale 1: +-0.06 m fore and aft (the
/// arms reach top-down grasps only about 0.04-0.11 m ahead, so part of the
/// time), +-0.02 m sideways, +-0.02 m up and down and +-0.1 rad of yaw.
Eigen::Isometry3d ScriptedDmo(double t_s, double period_s, double scale) {
  const Eigen::Vector3d centre_d = MissionConfig{}.grasp_dto_m;
  const double w = 2.0 * M_PI / period_s;
  const Eigen::Vector3d p_d =
      centre_d + scale * Eigen::Vector3d(0.06 * std::sin(w * t_s), 0.02 * std::sin(2.0 * w * t_s),
                                         0.02 * std::sin(w * t_s + 1.0));
  Eigen::Matrix3d dRo;  // columns x_o = y_d, y_o = x_d, z_o = -z_d
  dRo << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const double yaw = scale * 0.1 * std::sin(w * t_s + 2.0);
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();
  dMo.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * dRo;
  dMo.translation() = p_d;
  return dMo;
}

/// The bench needs a world it can move the object in and a camera that sees
/// that world; say what does not fit instead of faking it.
void CheckBenchHardware(const HardwareConfig& config) {
  const std::string& f = config.source;
  if (config.camera.backend != "sim") {
    throw ConfigError(
        fmt::format("{}: camera.backend: '{}': the bench moves the object by script in the "
                    "simulated world, which only the "
                    "simulated camera ('sim') sees; a bench with a real camera (the object moved "
                    "by hand) is not supported yet",
                    f, config.camera.backend));
  }
  if (config.arms.backend == "scs") {
    throw ConfigError(
        fmt::format("{}: arms.backend: 'scs' drives the real arms, but the camera is simulated: "
                    "the servo error would compare "
                    "real arms with a simulated object; use 'sim-bus' (the real driver, simulated "
                    "servos) or 'sim'",
                    f));
  }
  if (config.autopilot.backend == "px4") {
    throw ConfigError(fmt::format(
        "{}: autopilot.backend: 'px4' is a real vehicle, but the bench's vehicle is the "
        "simulated one on its stand; use 'sim-px4' or 'sim'",
        f));
  }
}

struct Stats {
  std::vector<double> t_err_m, r_err_deg;
  void Add(const PoseError& e) {
    t_err_m.push_back(e.translation_m);
    r_err_deg.push_back(kRadToDeg * e.rotation_rad);
  }
  static double Rms(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x * x;
    return v.empty() ? kNaN : std::sqrt(s / v.size());
  }
  nlohmann::json Json() const {
    return {{"frames", t_err_m.size()},
            {"translation_rmse_m", Rms(t_err_m)},
            {"rotation_rmse_deg", Rms(r_err_deg)},
            {"translation_median_m", Percentile(t_err_m, 0.5, kNaN)},
            {"rotation_median_deg", Percentile(r_err_deg, 0.5, kNaN)}};
  }
};

/// NaN (not finite) numbers become null, recursively.
void NullNonFinite(nlohmann::json* j) {
  if (j->is_number_float() && !std::isfinite(j->get<double>())) {
    *j = nullptr;
  } else if (j->is_object() || j->is_array()) {
    for (auto& v : *j) NullNonFinite(&v);
  }
}

/// One arm's servo error over time: to the commanded target and, in
/// simulation, to the same target on the true object.
struct ServoTrace {
  std::vector<double> t_s, to_target_m, to_truth_m;
};

void WriteServoErrorPlot(const ServoTrace traces[2], const std::string& path) {
  constexpr int kWidth = 1200, kHeight = 220, kLeft = 80, kTop = 30, kGap = 50;
  cv::Mat image(kTop + 2 * (kHeight + kGap), kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  double t0 = std::numeric_limits<double>::infinity(), t1 = -t0;
  for (int a = 0; a < 2; ++a) ExpandRange(traces[a].t_s, &t0, &t1);
  if (!std::isfinite(t0) || t1 <= t0) t0 = 0.0, t1 = 1.0;
  for (int a = 0; a < 2; ++a) {
    double lo = 0.0, hi = 0.01;
    ExpandRange(traces[a].to_target_m, &lo, &hi);
    ExpandRange(traces[a].to_truth_m, &lo, &hi);
    hi = std::min(hi, 0.2);
    const PlotPanel panel{
        fmt::format("{} arm: tool to its target (m): to the commanded target blue, to the target "
                    "on the true object orange; gaps: no target",
                    SideName(kSides[a])),
        t0,
        t1,
        0.0,
        1.05 * hi,
        kLeft,
        kTop + a * (kHeight + kGap),
        kWidth - kLeft - 20,
        kHeight};
    DrawPanelAxes(&image, panel, "", 3);
    DrawPanelSeries(&image, panel, traces[a].t_s, traces[a].to_truth_m, PlotColor{30, 140, 230}, 1);
    DrawPanelSeries(&image, panel, traces[a].t_s, traces[a].to_target_m, PlotColor{200, 60, 30}, 2);
    DrawPanelTimeLabels(&image, panel);
  }
  WritePlotPng(image, path);
}

void AddTrace(PoseTrace* trace, double t_s, bool ok, const Eigen::Isometry3d& cMo,
              double rotation_error_deg) {
  trace->stamp_s.push_back(t_s);
  trace->x_m.push_back(ok ? cMo.translation().x() : kNaN);
  trace->y_m.push_back(ok ? cMo.translation().y() : kNaN);
  trace->z_m.push_back(ok ? cMo.translation().z() : kNaN);
  trace->rotation_error_deg.push_back(rotation_error_deg);
  trace->found.push_back(ok ? 1 : 0);
}

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
  const MissionConfig mission =
      MissionConfig::Load(options.mission_config.empty() ? DataPath("config/mission_default.yaml")
                                                         : options.mission_config);
  // The mission's perception file unless one is given: the bench tests what the mission flies.
  const std::string perception_file =
      options.perception_config.empty() ? mission.perception : options.perception_config;
  const PerceptionOptions perception =
      perception_file.empty() ? PerceptionOptions{} : LoadPerceptionOptions(perception_file);

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
  // The test stand: the vehicle hovers in place with no sway, tilt, gusts or drift.
  const auto on_stand = [&](WorldConfig* w) {
    if (!options.object.empty()) w->object.name = options.object;
    w->object.motion = "static";
    w->vehicle.start = "hover";
    w->vehicle.sway_amplitude_m.setZero();
    w->vehicle.tilt_amplitude_rad = 0.0;
    w->vehicle.gust_rate_hz = 0.0;
    w->vehicle.drift_std_m = 0.0;
  };
  std::unique_ptr<Hardware> hw = Hardware::Open(hw_config, options.seed, on_stand);
  World* world = hw->world();
  if (!world)
    throw ConfigError(hw_config.source +
                      ": the bench needs a simulated world (no device is simulated)");
  const Platform& platform = hw->platform();
  const ObjectModel& object = world->object();

  const TagBoardConfig board = BenchBoard();
  const Eigen::Isometry3d oMt = options.oMt ? *options.oMt : DefaultBoardOnObject(object.mesh_o);
  world->AttachToObject(MakeBoardRenderMesh(board), oMt);
  TagDetector tag_detector(board.family);

  std::unique_ptr<BoxDetector> box_detector;
  const fs::path onnx = fs::path(object.source).parent_path() / "detector.onnx";
  if (fs::exists(onnx)) box_detector = std::make_unique<BoxDetector>(onnx.string());
  ObjectTracker tracker(object, perception, std::move(box_detector));
  const ObjectSymmetry& symmetry = tracker.model().symmetry;

  // Grasps as the mission plans them; the pre-catch pose, which the planner
  // checks for reach, is the hover point.
  const bool hover = options.hover_m > 0.0;
  GraspPlannerConfig planner_config = mission.planner;
  if (hover) planner_config.precatch_distance_m = options.hover_m;
  planner_config.Validate(cli, platform.config().gripper);
  GraspPlanner planner(
      platform, GraspObject{object.name, object.mesh_o, object.mass_kg, object.center_of_mass_o},
      ComputeContactPairs(object.mesh_o, platform.config().gripper, planner_config.contacts),
      planner_config);
  // The servo and grasp sequence of the mission's config.
  const PlatformCollision collision(platform);
  Eigen::VectorXd q[2];
  std::unique_ptr<ArmServo> servo[2];
  std::unique_ptr<GraspSequence> sequence[2];
  for (int a = 0; a < 2; ++a) {
    q[a] = hw->arms().JointPositions(kSides[a]);
    ArmController c = MakeArmController(mission, platform, kSides[a], collision, &q[1 - a],
                                        planner_config.precatch_distance_m);
    servo[a] = std::move(c.servo);
    sequence[a] = std::move(c.sequence);
    sequence[a]->HoldAtPreCatch(
        hover);  // hover: stay at the pre-catch pose; else move in (the gripper stays open)
  }

  fs::create_directories(options.out_dir);
  const std::string csv_path = (fs::path(options.out_dir) / "frames.csv").string();
  std::ofstream csv(csv_path);
  if (!csv) throw std::runtime_error(csv_path + ": cannot be written");
  csv << "frame,t_s,tags_ok,tags_used,tag_reprojection_px,found,tags_tx_m,tags_ty_m,tags_tz_m,est_"
         "tx_m,est_ty_m,"
         "est_tz_m,err_translation_m,err_rotation_deg,tags_truth_translation_m,tags_truth_rotation_"
         "deg,"
         "left_servo_error_m,right_servo_error_m\n";

  const Eigen::Isometry3d wMd = world->wMd();  // fixed on the stand
  const Eigen::Isometry3d& dMc = platform.dMc();
  const double dt_s = 1.0 / mission.servo_rate_hz;
  const double frame_period_s = 1.0 / world->config().camera.frame_rate_hz;
  const double t_start = world->now_s();
  auto place_object = [&](double t_s) {
    world->PlaceObject(wMd * ScriptedDmo(t_s - t_start, options.path_period_s, options.path_scale));
  };

  Stats perception_vs_tags, tags_vs_truth, perception_vs_truth;
  int tag_frames = 0, found_frames = 0, plans = 0, no_grasp_plans = 0, switches = 0;
  std::vector<double> frame_ms;
  std::vector<double> servo_error_tracking_m, servo_error_all_m, servo_error_to_truth_m;
  ServoTrace servo_traces[2];
  std::map<std::string, int> status_cycles;  // servo cycles per status, both arms
  PoseTrace tags_trace, est_trace;
  tags_trace.name = "tags";
  est_trace.name = "perception";
  MissionRecord record;
  record.object_name = object.name;
  for (int a = 0; a < 2; ++a) record.joint_names[a] = platform.arm(kSides[a]).joint_names();

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
  while (frame < options.frames) {
    const double t = world->now_s();
    for (int a = 0; a < 2; ++a) q[a] = hw->arms().JointPositions(kSides[a]);

    if (t + 1e-9 >= next_frame_s) {
      next_frame_s += frame_period_s;
      hw->camera().Grab(&rgbd);
      const CameraIntrinsics& K = hw->camera().intrinsics();
      // The tags' independent pose of the object.
      const BoardPose board_pose = EstimateBoardPose(tag_detector.Detect(rgbd.color), board, K);
      const bool tags_ok = board_pose.valid && board_pose.tags_used >= kMinBoardTags &&
                           board_pose.reprojection_rms_px <= kMaxTagReprojectionPx;
      const Eigen::Isometry3d cMo_tags = board_pose.cMt * oMt.inverse();
      // Our perception, as in replay and the mission (the filter in the camera frame: the camera
      // stands still).
      const FrameReport r =
          tracker.Process(rgbd.color, rgbd.depth, rgbd.stamp_s, K, hw->camera().depth_scale_m());
      frame_ms.push_back(r.times.total_ms);
      const bool found = r.estimate.valid && r.estimate.state == TrackState::kFound;
      if (found) estimate = r.estimate;
      // Lost (the arms come between the camera and the object): the last found
      // pose seeds the next frame, as the mission's held world pose does (the
      // camera stands still, the object moves slowly).
      if (!found && estimate) tracker.SetInitialPose(estimate->cMo);
      const Eigen::Isometry3d cMo_truth = world->wMc().inverse() * world->wMo();
      tag_frames += tags_ok;
      found_frames += found;
      double err_t = kNaN, err_r = kNaN, tags_truth_t = kNaN, tags_truth_r = kNaN;
      if (tags_ok && found) {
        const PoseError e{
            ComparePoses(cMo_tags, r.estimate.cMo).translation_m,
            SymmetricRotationError(r.estimate.cMo.linear(), cMo_tags.linear(), symmetry)};
        perception_vs_tags.Add(e);
        err_t = e.translation_m, err_r = kRadToDeg * e.rotation_rad;
      }
      if (tags_ok) {
        const PoseError e =
            ComparePoses(cMo_truth, cMo_tags);  // the board breaks the object's symmetry
        tags_vs_truth.Add(e);
        tags_truth_t = e.translation_m, tags_truth_r = kRadToDeg * e.rotation_rad;
      }
      if (found) {
        perception_vs_truth.Add(
            {ComparePoses(cMo_truth, r.estimate.cMo).translation_m,
             SymmetricRotationError(r.estimate.cMo.linear(), cMo_truth.linear(), symmetry)});
      }
      AddTrace(&tags_trace, t - t_start, tags_ok, cMo_tags, kNaN);
      AddTrace(&est_trace, t - t_start, found, r.estimate.cMo, err_r);
      MissionSample sample;
      sample.t_s = t - t_start;
      sample.found = found;
      for (int a = 0; a < 2; ++a)
        sample.q_target_rad[a] = q_command[a], sample.q_actual_rad[a] = q[a];
      record.samples.push_back(sample);
      if (found && tags_ok && (!record.snapshot || frame == options.frames / 2)) {
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
        record.snapshot = snap;
      }
      const double last_error[2] = {
          servo_traces[0].to_target_m.empty() ? kNaN : servo_traces[0].to_target_m.back(),
          servo_traces[1].to_target_m.empty() ? kNaN : servo_traces[1].to_target_m.back()};
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
          DecideSwitch(planner.Plan(query), choice, mission.policy.switch_margin);
      ++plans;
      if (decision.status == SwitchDecision::Status::kNoGrasp) {
        ++no_grasp_plans;
        has_grasp = false;
      } else {
        const bool changed = !has_grasp || decision.status == SwitchDecision::Status::kSwitch;
        switches += has_grasp && decision.status == SwitchDecision::Status::kSwitch;
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
        if (planner.EvaluateArm(side, pair[a], dMo, q[a], &solved, &why) &&
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
        ++status_cycles[ServoStatusName(status)];
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
          Eigen::Isometry3d cMo_truth = world->wMc().inverse() * world->wMo();
          cMo_truth.linear() =
              ClosestSymmetricRotation(cMo_truth.linear(), estimate->cMo.linear(), symmetry);
          const Eigen::Isometry3d bMh_truth = bMd * dMc * cMo_truth * bMo.inverse() * bMh;
          to_truth = (p_b - bMh_truth.translation()).norm();
          tracking[a] = tracking[a] || to_target < kTrackingWithinM;
          servo_error_all_m.push_back(to_target);
          if (tracking[a]) {
            servo_error_tracking_m.push_back(to_target);
            servo_error_to_truth_m.push_back(to_truth);
          }
        } else {
          tracking[a] = false;
        }
      }
      servo_traces[a].t_s.push_back(t - t_start);
      servo_traces[a].to_target_m.push_back(to_target);
      servo_traces[a].to_truth_m.push_back(to_truth);
    }
    hw->StepSimulation(dt_s);
    place_object(world->now_s());
  }
  bar.Finish();
  csv.close();

  // summary.json
  const Eigen::Vector4d q_t = QuaternionWxyz(oMt);
  nlohmann::json summary;
  summary["object"] = object.name;
  summary["hardware"] = hw_config.source;
  summary["seed"] = options.seed;
  summary["perception"] = perception_file.empty() ? "code defaults" : perception_file;
  summary["frames"] = frame;
  summary["tag_frames"] = tag_frames;
  summary["found_frames"] = found_frames;
  summary["compared_frames"] = perception_vs_tags.t_err_m.size();
  summary["translation_rmse_m"] = Stats::Rms(perception_vs_tags.t_err_m);
  summary["rotation_rmse_deg"] = Stats::Rms(perception_vs_tags.r_err_deg);
  summary["translation_median_m"] = Percentile(perception_vs_tags.t_err_m, 0.5, kNaN);
  summary["rotation_median_deg"] = Percentile(perception_vs_tags.r_err_deg, 0.5, kNaN);
  summary["rotation_error"] =
      "perception vs tags: angle minimised over the object's rotational symmetries";
  summary["servo_target"] = options.hover_m > 0.0
                                ? fmt::format("hover {:.3f} m off the grasp", options.hover_m)
                                : std::string("the grasp");
  summary["hover_m"] = options.hover_m;
  summary["servo_error_m_median"] = Percentile(servo_error_tracking_m, 0.5, kNaN);
  summary["servo_error_m_p95"] = Percentile(servo_error_tracking_m, 0.95, kNaN);
  summary["servo_tracking_cycles"] = servo_error_tracking_m.size();
  summary["servo_error_m_median_all_cycles"] = Percentile(servo_error_all_m, 0.5, kNaN);
  summary["servo_error_definition"] =
      "distance from the tool point (measured joints) to its target (the estimated object times "
      "the planned grasp "
      "or hover point), over the servo cycles an arm tracks: from its first cycle within 0.01 m of "
      "the target "
      "until the grasp changes or the target is refused; _all_cycles counts every moving cycle";
  summary["servo_status_cycles"] = status_cycles;
  summary["grasp_plans"] = plans;
  summary["grasp_plans_without_grasp"] = no_grasp_plans;
  summary["grasp_switches"] = switches;
  summary["frame_ms_median"] = Percentile(frame_ms, 0.5, kNaN);
  summary["board"] = {{"family", board.family},
                      {"rows", board.rows},
                      {"cols", board.cols},
                      {"tag_size_m", board.tag_size_m},
                      {"spacing_m", board.spacing_m},
                      {"first_id", board.first_id},
                      {"oMt_xyz_qwxyz",
                       {oMt.translation().x(), oMt.translation().y(), oMt.translation().z(), q_t[0],
                        q_t[1], q_t[2], q_t[3]}}};
  summary["tags_vs_truth"] = tags_vs_truth.Json();
  summary["perception_vs_truth"] = perception_vs_truth.Json();
  summary["servo_error_to_truth_m_median"] = Percentile(servo_error_to_truth_m, 0.5, kNaN);
  NullNonFinite(&summary);
  const std::string summary_path = WriteSummaryFile(options.out_dir, summary.dump(2));

  // The report.
  const fs::path dir(options.out_dir);
  const bool has_tags = tag_frames > 0;
  if (has_tags)
    WritePosePlot(tags_trace, {est_trace}, (dir / "pose_vs_tags.png").string(), "cMo position");
  WriteServoErrorPlot(servo_traces, (dir / "servo_error.png").string());
  const bool has_joints = WriteMissionJointPlot(record, (dir / "joints.png").string());
  if (record.snapshot)
    WriteMissionCameraImage(*record.snapshot, object.mesh_o, (dir / "camera.png").string());
  auto num = [&](const char* key, double scale, int decimals = 2) {
    return summary[key].is_number()
               ? fmt::format("{:.{}f}", scale * summary[key].get<double>(), decimals)
               : std::string("-");
  };
  std::ostringstream html;
  BeginHtmlPage("Bench report: " + object.name, html);
  WriteHtmlTable(
      {"result", "value"},
      {{"frames", std::to_string(frame)},
       {"frames with the board (tags)", std::to_string(tag_frames)},
       {"frames with the object found", std::to_string(found_frames)},
       {"perception vs tags: translation RMSE (mm)", num("translation_rmse_m", 1e3)},
       {"perception vs tags: rotation RMSE (deg)", num("rotation_rmse_deg", 1)},
       {"servo target", summary["servo_target"].get<std::string>()},
       {"servo error median while tracking (mm)", num("servo_error_m_median", 1e3)},
       {"servo error p95 while tracking (mm)", num("servo_error_m_p95", 1e3)},
       {"tags vs truth: translation RMSE (mm)",
        summary["tags_vs_truth"]["translation_rmse_m"].is_number()
            ? fmt::format("{:.2f}",
                          1e3 * summary["tags_vs_truth"]["translation_rmse_m"].get<double>())
            : "-"},
       {"hardware", hw_config.source}},
      html);
  html << "<h2>Perception against the tags</h2>\n";
  WriteHtmlFigure(has_tags, "pose_vs_tags.png",
                  "The object's position in the camera frame (cMo), from the tag board (black) and "
                  "from perception; "
                  "perception's rotation error against the tags (deg, over the object's "
                  "symmetries) and whether it "
                  "had the object.",
                  "The board was never seen.", html);
  html << "<h2>Servo</h2>\n";
  WriteHtmlFigure(true, "servo_error.png",
                  "Each arm's tool point to its target (the planned grasp, or the hover point off "
                  "it) over time.",
                  "", html);
  WriteHtmlFigure(has_joints, "joints.png",
                  "Joint targets (thin) vs measured positions (thick) of each arm, deg.",
                  "No joint samples were recorded.", html);
  html << "<h2>Camera</h2>\n";
  WriteHtmlFigure(
      record.snapshot.has_value(), "camera.png",
      record.snapshot
          ? fmt::format("Camera frame at t = {:.2f} s: the detector box (green) and the object "
                        "model at the estimated pose cMo (cyan).",
                        record.snapshot->t_s)
          : std::string(),
      "No frame had both the board and the object.", html);
  WriteHtmlPage(html.str(), options.out_dir);

  out << fmt::format("bench: {} frames, object {}, {}\n", frame, object.name, hw_config.source);
  out << fmt::format("  board seen in {} frames, object found in {}, both in {}\n", tag_frames,
                     found_frames, perception_vs_tags.t_err_m.size());
  out << fmt::format("  perception vs tags: translation RMSE {} mm, rotation RMSE {} deg\n",
                     num("translation_rmse_m", 1e3), num("rotation_rmse_deg", 1));
  if (tags_vs_truth.t_err_m.size()) {
    out << fmt::format("  tags vs truth: translation RMSE {:.2f} mm, rotation RMSE {:.3f} deg\n",
                       1e3 * Stats::Rms(tags_vs_truth.t_err_m),
                       Stats::Rms(tags_vs_truth.r_err_deg));
  }
  out << fmt::format(
      "  servo to {}: error median {} mm, p95 {} mm over {} tracking cycles ({} plans, {} without "
      "a grasp)\n",
      summary["servo_target"].get<std::string>(), num("servo_error_m_median", 1e3),
      num("servo_error_m_p95", 1e3), servo_error_tracking_m.size(), plans, no_grasp_plans);
  out << "  wrote " << summary_path << ", " << (dir / "index.html").string() << "\n";

  if (tag_frames == 0) {
    throw std::runtime_error(fmt::format(
        "bench: the tag board was never detected in {} frames (board {}x{} tags of {:.0f} mm, ids "
        "from {}, on the "
        "object at oMt translation {:.3f} {:.3f} {:.3f} m): is its printed face towards the camera "
        "(--board-pose)? "
        "See {}/frames.csv",
        frame, board.rows, board.cols, 1e3 * board.tag_size_m, board.first_id,
        oMt.translation().x(), oMt.translation().y(), oMt.translation().z(), options.out_dir));
  }
  if (found_frames == 0) {
    throw std::runtime_error(
        fmt::format("bench: perception never found the object ({}) in {} frames; see {}/frames.csv",
                    object.name, frame, options.out_dir));
  }
}

}  // namespace aerograsp
