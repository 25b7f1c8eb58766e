#include "app/calibration/calibration_hardware.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "app/calibration/tag_board_mesh.h"
#include "app/runtime/telemetry_frames.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/transforms.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace {

constexpr double kDeg = M_PI / 180.0;

bool RealArms(const HardwareConfig& c) { return c.arms.backend == "scs"; }
bool RealCamera(const HardwareConfig& c) { return c.camera.backend == "realsense"; }

/// The board must be in front of the camera that is used: real arms with the
/// real camera, simulated arms with the simulated camera.
void CheckHandEyeMix(const HardwareConfig& config, const CalibrationRig& rig) {
  const std::string& f = config.source;
  if (config.camera.backend == "replay") {
    throw ConfigError(fmt::format(
        "{}: camera.backend: 'replay': a recorded sequence cannot follow the poses the wizard "
        "plans; re-solve a recorded data set with `calibrate --resolve DIR`",
        f));
  }
  if (RealArms(config) && !RealCamera(config)) {
    throw ConfigError(fmt::format(
        "{}: arms.backend: 'scs' drives the real arms, but camera.backend '{}' is simulated: the "
        "board on the real gripper is not in front of that camera; use camera.backend "
        "'realsense' (or 'sim-bus' / 'sim' arms)",
        f, config.camera.backend));
  }
  if (!RealArms(config) && RealCamera(config)) {
    throw ConfigError(
        fmt::format("{}: camera.backend: 'realsense' is the real camera, but arms.backend '{}' is "
                    "simulated: a simulated gripper shows no board to it; use arms.backend 'scs'",
                    f, config.arms.backend));
  }
  if (rig.mount != "gripper") {
    throw ConfigError(fmt::format(
        "{}: calibration.mount: '{}': the camera-to-arm calibration needs the board on the "
        "gripper ('gripper'); a board held by hand is for `calibrate --intrinsics`",
        rig.source, rig.mount));
  }
}

}  // namespace

CalibrationRig CalibrationRig::Load(const std::string& hardware_path) {
  CalibrationRig r;
  r.source = hardware_path;
  r.eMt = MakeTransform(Eigen::Vector3d(0.0, 0.0, 0.025), Eigen::Vector3d::Zero());
  if (hardware_path.empty()) {
    r.source = "built-in simulation";
    return r;
  }
  const ConfigNode root = ConfigNode::LoadFile(hardware_path);
  if (!root.Has("calibration")) return r;
  const ConfigNode n = root.Child("calibration");
  n.RequireOnlyKeys({"mount", "board", "board_in_tool_xyz_m", "board_in_tool_rpy_deg",
                     "joint_speed_deg_s", "settle_timeout_s", "settle_tolerance_deg",
                     "settle_window_s", "min_voltage_v", "max_voltage_v", "max_temperature_c",
                     "max_failed_reads", "still_px", "max_missed_frames", "coverage"});
  r.mount = n.GetString("mount", r.mount);
  if (n.Has("board")) r.board = TagBoardConfig::FromNode(n.Child("board"));
  const Eigen::Vector3d xyz =
      n.Has("board_in_tool_xyz_m") ? n.GetVector3("board_in_tool_xyz_m") : r.eMt.translation();
  const Eigen::Vector3d rpy = n.Has("board_in_tool_rpy_deg")
                                  ? Eigen::Vector3d(n.GetVector3("board_in_tool_rpy_deg") * kDeg)
                                  : Eigen::Vector3d::Zero();
  r.eMt = MakeTransform(xyz, rpy);
  r.joint_speed_deg_s = n.GetDouble("joint_speed_deg_s", r.joint_speed_deg_s);
  r.settle_timeout_s = n.GetDouble("settle_timeout_s", r.settle_timeout_s);
  r.settle_tolerance_deg = n.GetDouble("settle_tolerance_deg", r.settle_tolerance_deg);
  r.settle_window_s = n.GetDouble("settle_window_s", r.settle_window_s);
  r.min_voltage_v = n.GetDouble("min_voltage_v", r.min_voltage_v);
  r.max_voltage_v = n.GetDouble("max_voltage_v", r.max_voltage_v);
  r.max_temperature_c = n.GetDouble("max_temperature_c", r.max_temperature_c);
  r.max_failed_reads = n.GetInt("max_failed_reads", r.max_failed_reads);
  r.still_px = n.GetDouble("still_px", r.still_px);
  r.max_missed_frames = n.GetInt("max_missed_frames", r.max_missed_frames);
  if (n.Has("coverage")) r.coverage = CoverageConfig::FromNode(n.Child("coverage"));
  r.Validate(r.source, "calibration.");
  return r;
}

void CalibrationRig::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& f = source;
  CheckOneOf(f, prefix + "mount", mount, {"gripper", "hand"});
  board.Validate(f, prefix + "board.");
  CheckRange(f, prefix + "board_in_tool_xyz_m", Eigen::Vector3d(eMt.translation()), -0.5, 0.5, "m");
  CheckRange(f, prefix + "joint_speed_deg_s", joint_speed_deg_s, 0.1, 180.0, "deg/s");
  CheckRange(f, prefix + "settle_timeout_s", settle_timeout_s, 0.001, 60.0, "s");
  CheckRange(f, prefix + "settle_tolerance_deg", settle_tolerance_deg, 0.01, 10.0, "deg");
  CheckRange(f, prefix + "settle_window_s", settle_window_s, 0.0, 5.0, "s");
  CheckRange(f, prefix + "min_voltage_v", min_voltage_v, 0.0, 30.0, "V");
  CheckRange(f, prefix + "max_voltage_v", max_voltage_v, min_voltage_v, 30.0, "V");
  CheckRange(f, prefix + "max_temperature_c", max_temperature_c, 0.0, 120.0, "C");
  CheckRange(f, prefix + "max_failed_reads", max_failed_reads, 1, 100, "");
  CheckRange(f, prefix + "still_px", still_px, 0.01, 20.0, "px");
  CheckRange(f, prefix + "max_missed_frames", max_missed_frames, 1, 1000, "");
  coverage.Validate(f, prefix + "coverage.");
}

HandEyeHardware::~HandEyeHardware() {
  // The driver first (it talks to the bus), then the bus, then the world.
  arms_.reset();
  camera_.reset();
  sim_bus_.reset();
  world_.reset();
}

std::string HandEyeHardware::ArmsWhere() const {
  if (config_.arms.backend == "scs")
    return fmt::format("scs on {} at {} baud", config_.arms.scs.port, config_.arms.scs.baud);
  if (sim_bus_) return "simulated SCS bus on " + sim_bus_->port_path();
  return "in-process simulator";
}

double HandEyeHardware::now_s() const { return world_ ? world_->now_s() : SteadySeconds(); }

std::string HandEyeHardware::PollEmergencyStop() {
  if (!emergency_stop_) return "";
  const EmergencyStopPoll poll = emergency_stop_->Poll(now_s());
  if (emergency_note_) {
    for (const std::string& note : poll.notes) emergency_note_(note);
  }
  if (!poll.stop) return "";
  return "emergency stop from " + poll.source + (poll.reason.empty() ? "" : ": " + poll.reason);
}

void HandEyeHardware::Wait(double dt_s) {
  if (!world_) {
    std::this_thread::sleep_for(std::chrono::duration<double>(dt_s));
  } else {
    if (scs_) scs_->Cycle();
    if (sim_bus_) sim_bus_->SyncWithWorld();
    world_->Step(dt_s);
  }
  if (telemetry_) {
    const Eigen::VectorXd q[2] = {arms_->JointPositions(Side::kLeft),
                                  arms_->JointPositions(Side::kRight)};
    telemetry_->Arms(ArmsState(now_s(), *platform_, q, *arms_));
    telemetry_->Transforms(now_s(), ToolFrames(*platform_, q));
  }
}

void HandEyeHardware::Arm(std::optional<Side> limp) {
  if (!scs_) return;
  if (scs_->SetTorque(true) != BusStatus::kOk)
    throw HardwareError("servo bus " + config_.arms.scs.port + ": torque could not be enabled");
  if (limp && scs_->SetTorque(*limp, false) != BusStatus::kOk) {
    throw HardwareError("servo bus " + config_.arms.scs.port + ": the " + SideName(*limp) +
                        " arm's torque could not be turned off");
  }
  if (!world_) scs_->StartThread();
}

void HandEyeHardware::Stiffen(Side side) {
  if (!scs_) return;
  if (!world_) scs_->StopThread();
  // The command follows the readings first: the servos hold where the hand left them.
  arms_->SetJointTargets(side, arms_->JointPositions(side));
  scs_->Cycle();
  if (scs_->SetTorque(side, true) != BusStatus::kOk) {
    throw HardwareError("servo bus " + config_.arms.scs.port + ": the " + SideName(side) +
                        " arm's torque could not be enabled");
  }
  if (!world_) scs_->StartThread();
}

std::unique_ptr<HandEyeHardware> OpenHandEyeHardware(const std::string& hardware_path,
                                                     const std::string& world_path,
                                                     std::uint64_t seed, Side side,
                                                     std::ostream& out) {
  std::unique_ptr<HandEyeHardware> hw(new HandEyeHardware());
  if (hardware_path.empty()) {
    const std::string world =
        world_path.empty() ? DataPath("config/world_default.yaml") : world_path;
    hw->config_ = HardwareConfig::InProcessSimulation(WorldConfig::Load(world).platform, world);
  } else {
    hw->config_ = HardwareConfig::Load(hardware_path);
    if (!world_path.empty()) hw->config_.world = world_path;
  }
  hw->rig_ = CalibrationRig::Load(hardware_path);
  const HardwareConfig& config = hw->config_;
  CheckHandEyeMix(config, hw->rig_);

  // The autopilot is not needed: the vehicle stands still while calibrating.
  const bool simulated = !RealArms(config);
  if (simulated) {
    WorldConfig world_config = WorldConfig::Load(config.world);
    world_config.platform = config.platform;
    hw->world_ = std::make_unique<World>(world_config, seed);
    hw->platform_ = std::make_unique<Platform>(hw->world_->platform());
    // The simulated rig: the board where the hardware file says it is fixed.
    hw->world_->AttachToTool(side, MakeBoardRenderMesh(hw->rig_.board), hw->rig_.eMt);
  } else {
    hw->platform_ = std::make_unique<Platform>(Platform::Load(config.platform));
  }
  std::vector<std::string> failures;
  out << fmt::format("devices ({}):\n", config.source);
  try {
    hw->arms_ =
        OpenArms(config.arms, *hw->platform_, hw->world_.get(), &hw->sim_bus_, /*torque_on=*/false);
    hw->scs_ = dynamic_cast<ScsArmsDriver*>(hw->arms_.get());
    out << fmt::format("  {:<8} ok: {}\n", "arms", hw->ArmsWhere());
  } catch (const std::exception& e) {
    failures.push_back(fmt::format("arms ({}): {}", config.arms.backend, e.what()));
    out << "  arms     FAILED: " << e.what() << "\n";
  }
  try {
    hw->camera_ = OpenCamera(config.camera, hw->world_.get());
    out << fmt::format("  {:<8} ok: {}\n", "camera", config.camera.backend);
  } catch (const std::exception& e) {
    failures.push_back(fmt::format("camera ({}): {}", config.camera.backend, e.what()));
    out << "  camera   FAILED: " << e.what() << "\n";
  }
  if (!failures.empty()) {
    std::string all;
    for (const std::string& f : failures) all += "\n  " + f;
    throw HardwareError(fmt::format("{}: {} device(s) did not open; nothing moved:{}",
                                    config.source, failures.size(), all));
  }
  return hw;
}

std::vector<std::string> PreflightDevices(HandEyeHardware& hw, RgbdFrame* frame,
                                          std::ostream& out) {
  std::vector<std::string> failures;
  auto check = [&](bool ok, const std::string& what, const std::string& detail) {
    out << fmt::format("  {:<8} {}: {}\n", ok ? "ok" : "FAILED", what, detail);
    if (!ok) failures.push_back(what + ": " + detail);
  };
  const CalibrationRig& rig = hw.rig();
  const Platform& platform = hw.platform();
  out << "pre-flight:\n";
  if (ScsArmsDriver* scs = hw.scs()) {
    // One cycle per servo: each one's voltage and temperature are read once.
    const std::size_t servos = scs->servo_statuses().size();
    for (std::size_t i = 0; i < servos; ++i) scs->Cycle();  // the bus thread is not running yet
    for (const ScsServoStatus& s : scs->servo_statuses()) {
      const std::string name = fmt::format("servo {} (id {})", s.name, s.id);
      if (s.failed_reads > 0 || s.raw_position < 0) {
        check(false, name, fmt::format("does not answer on {}", hw.ArmsWhere()));
        continue;
      }
      const bool volt = s.voltage_v >= rig.min_voltage_v && s.voltage_v <= rig.max_voltage_v;
      const bool hot = s.temperature_c > rig.max_temperature_c;
      check(
          volt && !hot && s.error == 0, name,
          fmt::format("{:.1f} V (allowed {:.1f}-{:.1f}), {} C (at most {:.0f}){}", s.voltage_v,
                      rig.min_voltage_v, rig.max_voltage_v, s.temperature_c, rig.max_temperature_c,
                      s.error ? ", error bits: " + scs::ErrorBitsText(s.error) : ""));
    }
    for (Side side : kSides) {
      const std::size_t configured =
          hw.config().arms.servos_given ? hw.config().arms.scs.joints[static_cast<int>(side)].size()
                                        : static_cast<std::size_t>(platform.arm(side).dof());
      check(static_cast<int>(configured) == platform.arm(side).dof(),
            fmt::format("{} arm servos", SideName(side)),
            fmt::format("{} configured (arms.servos.{} in {}), the URDF has {} joints", configured,
                        SideName(side), hw.config().source, platform.arm(side).dof()));
    }
  }
  for (Side side : kSides) {
    const ArmModel& arm = platform.arm(side);
    const Eigen::VectorXd q = hw.arms().JointPositions(side);
    bool all_inside = true;
    for (int j = 0; j < arm.dof() && j < q.size(); ++j) {
      // Half a degree of slack: a servo resting on its stop reads a count past it.
      const double slack = 0.5 * kDeg;
      const bool inside =
          q[j] >= arm.lower_limits()[j] - slack && q[j] <= arm.upper_limits()[j] + slack;
      if (inside) continue;
      all_inside = false;
      check(false, fmt::format("{} j{}", SideName(side), j + 1),
            fmt::format("reads {:.1f} deg, outside the URDF's limits [{:.1f}, {:.1f}] deg: check "
                        "the servo's calibration (arms.servos.{}.j{} in {})",
                        q[j] / kDeg, arm.lower_limits()[j] / kDeg, arm.upper_limits()[j] / kDeg,
                        SideName(side), j + 1, hw.config().source));
    }
    std::string degrees;
    for (int j = 0; j < q.size(); ++j)
      degrees += fmt::format("{}{:.1f}", j ? ", " : "", q[j] / kDeg);
    check(q.size() == arm.dof() && all_inside, fmt::format("{} arm joints", SideName(side)),
          fmt::format("[{}] deg{}", degrees, all_inside ? ", inside the URDF's limits" : ""));
  }
  const CameraIntrinsics& K = hw.camera().intrinsics();
  const bool got = hw.camera().Grab(frame);
  const bool size_ok = got && frame->color.width == K.width && frame->color.height == K.height;
  check(got && size_ok && K.fx > 0.0 && K.fy > 0.0, "camera",
        got ? fmt::format("frame {} of {}x{} (intrinsics {}x{}, fx {:.1f} fy {:.1f})", frame->index,
                          frame->color.width, frame->color.height, K.width, K.height, K.fx, K.fy)
            : std::string("no frame: the stream is not running"));
  return failures;
}

}  // namespace aerograsp
