// One mission (paper Sect. 5): take-off, fly to the approach waypoint, find
// the object, hold it in the arms' workspace, plan a dual grasp, servo both
// arms to their pre-catch poses, move in and close, lift, fly home and land.
// The runner schedules; the grasp policy (mission/grasp_policy.h) and the five
// state machines (mission/state_machines.h) decide; the vehicle legs
// (app/runtime/mission_vehicle.h), the grasp scheduler (app/runtime/mission_grasp.h) and the
// arms (app/runtime/mission_arms.h) carry their answers out on the devices. The loop
// sees only what the robot sees; in simulation an evaluator
// (app/runtime/mission_evaluator.h) compares with the world's truth. docs/mission.md
// has the whole picture.
//
// Runtime: the servo loop at servo_rate_hz, perception at the camera's rate
// on its own thread (a frame's result is used one camera period after it was
// taken), grasp plans and re-evaluations on another thread (their answers are
// used one re-evaluation period after they were asked), position setpoints at
// setpoint_rate_hz. With simulated devices everything runs on the simulated
// clock, as fast as the machine allows, and a seed gives the same mission
// every time; with real devices, on the wall clock. Any exception becomes an
// emergency stop (arms stop, vehicle holds) with the message kept.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "app/runtime/mission_record.h"
#include "telemetry/telemetry.h"

namespace aerograsp {

struct HardwareConfig;
struct MissionSetup;
struct WorldConfig;

struct MissionOptions {
  std::string config_path;    ///< mission YAML; empty: data/config/mission_default.yaml
  std::string hardware_path;  ///< hardware YAML; empty: every device simulated in-process
  std::uint64_t seed{1};
  std::string object;            ///< shipped object name or model path; empty: the world's
  std::string arm_type{"4dof"};  ///< "4dof" | "6dof" (the platform config)
  /// hover sway per horizontal axis (vertical 2/3 of it); < 0: the world's
  double sway_amplitude_m{-1.0};
  double sway_frequency_hz{-1.0};  ///< < 0: the world's
  std::string motion;              ///< "static" | "crawl"; empty: the world's
  double object_speed_mps{-1.0};   ///< crawl speed; < 0: the world's
  double timeout_s{-1.0};          ///< < 0: the mission config's
  /// When given: changes the hardware configuration after it is read (faults
  /// on simulated devices, for the fault benchmark).
  std::function<void(HardwareConfig*)> adjust_hardware;
  /// When given: changes the simulated world's settings after the options above.
  std::function<void(WorldConfig*)> adjust_world;
  /// When given: the planner and placement of an earlier mission of the same
  /// configuration (app/runtime/mission_setup.h), reused when it is one; filled
  /// when it is empty or of another configuration.
  std::shared_ptr<MissionSetup> setup;
};

/// One gripper close, measured against the simulated world's truth
/// (app/runtime/mission_evaluator.h).
struct GripperClose {
  double t_s = 0.0;    ///< when the close ended (the fingers stopped)
  int arm = 0;         ///< 0 left, 1 right
  bool holds = false;  ///< the gripper held the object when the close ended
  /// The tool point against its grasp point on the true object at contact, m:
  /// measured when the close ends (a holding gripper carries the object fixed
  /// to the tool from the moment the pads touched it).
  double tool_error_m = 0.0;
};

struct MissionResult {
  bool success = false;         ///< landed with the object held by both grippers, no emergency
  std::string failure;          ///< why not, one line (empty on success)
  double time_to_grasp_s = -1;  ///< from the start to both grippers holding; < 0: never
  /// object position estimate vs truth over the frames found while grasping; < 0: none (or no
  /// truth: hardware)
  double pose_rmse_m = -1;
  double rotation_rmse_deg = -1;
  int grasp_frames = 0;    ///< frames the pose RMSE is taken over
  int grasp_switches = 0;  ///< re-evaluation switched the followed dual grasp
  /// Grasp attempts: dual grasps planned plus re-aims of a free arm while the
  /// other gripper holds (the planner machine's max_attempts counts failed plans only).
  int attempts = 0;
  /// Times an arm entered the safe volume: by the true joints in simulation
  /// (the evaluator), by the measured ones on hardware (the safety stop acts on
  /// the measured ones in both).
  int safe_volume_entries = 0;
  /// Times the two arms touched each other, by the true joints (simulation only).
  int arm_contacts = 0;
  int emergency_stops = 0;  ///< 0 or 1: the stop is latched, later causes are only logged
  /// Device faults found (each device and kind once), by kind
  /// (hardware/device_health.h: servo_silent, link_lost, camera_no_frame, ...).
  std::map<std::string, int> device_faults;
  /// Simulation: when a fault the hardware file sets on a simulated device first
  /// showed (Hardware::FirstSimulatedFaultS); < 0: none.
  double simulated_fault_s = -1;
  double sim_time_s = 0;  ///< mission time
  double wall_time_s = 0;
  double realtime_factor = 0;  ///< sim_time_s / wall_time_s
  /// CPU time of all the process's threads while the mission flew, s, and
  /// sim_time_s over it: the real-time factor on one core, whatever else runs.
  double cpu_time_s = 0;
  double realtime_factor_cpu = 0;
  int frames = 0;  ///< camera frames processed
  /// Frames on which the tracker ran a global registration (no usable prior,
  /// or the local registration from it failed).
  int global_registrations = 0;
  double perception_ms_median = 0;  ///< thread CPU per frame
  double render_ms_median = 0;      ///< simulated camera: wall time per frame
  /// Every gripper close with its truth (simulation only; empty on hardware).
  std::vector<GripperClose> closes;
  /// The arms' servo cycle (the planner's answers taken and its questions
  /// asked, the followed grasp solved again, both grasp sequences and
  /// servos): the longest, wall time and thread CPU time, ms.
  double servo_step_ms_max = 0;
  double servo_step_cpu_ms_max = 0;
};

/// Who hears the mission as it flies and who may stop it (each may be null;
/// both must outlive the call).
struct MissionLinks {
  /// Receives the static transforms at the start; the arms and the moving
  /// transforms every servo cycle; the object's pose and the camera frame at
  /// each processed frame; every transition, grasp pair and log line.
  TelemetrySink* telemetry = nullptr;
  /// Polled at the start of every servo cycle; a stop is the mission's
  /// emergency (arms stop, vehicle holds, the mission aborts) with the source
  /// in its cause.
  EmergencyStopSource* emergency_stop = nullptr;
};

/// Flies one mission. `log` (may be null) receives one line per transition and
/// event; `record` (may be null) receives the samples for the report.
/// @throws ConfigError / MeshError / HardwareError before take-off (bad files,
/// missing devices); once running, failures end the mission in the result.
MissionResult RunMission(const MissionOptions& options, MissionRecord* record, std::ostream* log,
                         const MissionLinks& links = {});

}  // namespace aerograsp
