// One mission (paper Sect. 5): take-off, fly to the approach waypoint, find
// the object, hold it in the arms' workspace, plan a dual grasp, servo both
// arms to their pre-catch poses, move in and close, lift, fly home and land.
// The five state machines (mission/state_machines.h) decide; this runner
// feeds them and carries out their states on the devices.
//
// Runtime: the servo loop at servo_rate_hz, perception at the camera's rate
// on its own thread (a frame's result is used one camera period after it was
// taken), grasp re-evaluation on another thread (its answer is used one
// re-evaluation period after it was asked), position setpoints at
// setpoint_rate_hz. With simulated devices everything runs on the simulated
// clock, as fast as the machine allows, and a seed gives the same mission
// every time; with real devices, on the wall clock. Any exception becomes an
// emergency stop (arms stop, vehicle holds) with the message kept.
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

#include "app/mission_record.h"

namespace aerograsp {

struct MissionOptions {
  std::string config_path;    ///< mission YAML; empty: data/config/mission_default.yaml
  std::string hardware_path;  ///< hardware YAML; empty: every device simulated in-process
  std::uint64_t seed{1};
  std::string object;            ///< shipped object name or model path; empty: the world's
  std::string arm_type{"4dof"};  ///< "4dof" | "6dof" (the platform config)
  double sway_amplitude_m{
      -1.0};  ///< hover sway per horizontal axis (vertical 2/3 of it); < 0: the world's
  double sway_frequency_hz{-1.0};  ///< < 0: the world's
  std::string motion;              ///< "static" | "crawl"; empty: the world's
  double object_speed_mps{-1.0};   ///< crawl speed; < 0: the world's
  double timeout_s{-1.0};          ///< < 0: the mission config's
};

struct MissionResult {
  bool success = false;         ///< landed with the object held by both grippers, no emergency
  std::string failure;          ///< why not, one line (empty on success)
  double time_to_grasp_s = -1;  ///< from the start to both grippers holding; < 0: never
  double pose_rmse_m =
      -1;  ///< object position estimate vs truth over the frames found while grasping; < 0: none
  double rotation_rmse_deg = -1;
  int grasp_switches = 0;       ///< re-evaluation switched the followed dual grasp
  int attempts = 0;             ///< plans started
  int safe_volume_entries = 0;  ///< times an arm entered the safe volume (true joints)
  int emergency_stops = 0;
  double sim_time_s = 0;  ///< mission time
  double wall_time_s = 0;
  double realtime_factor = 0;  ///< sim_time_s / wall_time_s
  int frames = 0;              ///< camera frames processed
  int global_registrations =
      0;  ///< frames on which the tracker searched the whole crop (no usable prior)
  double perception_ms_median = 0;  ///< thread CPU per frame
  double render_ms_median = 0;      ///< simulated camera: wall time per frame
};

/// Flies one mission. `log` (may be null) receives one line per transition and
/// event; `record` (may be null) receives the samples for the report.
/// @throws ConfigError / MeshError / HardwareError before take-off (bad files,
/// missing devices); once running, failures end the mission in the result.
MissionResult RunMission(const MissionOptions& options, MissionRecord* record, std::ostream* log);

}  // namespace aerograsp
