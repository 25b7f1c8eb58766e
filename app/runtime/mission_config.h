// The mission's settings, one validated tree (data/config/mission_default.yaml
// is the reference and equals the defaults here): the simulated world it flies
// in, its waypoints, where the object should sit in the body frame for the
// grasp, loop rates, tolerances and time limits, and the nested settings of
// the grasp policy, the grasp planner, the arm servo and the grasp sequence.
// `bench` reads the same tree. Frame w is NED with its origin at the take-off
// point; d is FRD.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "grasp/placement.h"
#include "grasp/planner.h"
#include "mission/grasp_policy.h"
#include "servo/arm_servo.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {

/// The planner as the mission sets it: contacts 2.5 cm to 10 cm behind the
/// tool point, grasps feasible through 2 cm of sway and 1.5 cm clear of the
/// faces' edges first.
GraspPlannerConfig MissionPlannerDefaults();
/// The servo as the mission sets it (gain 15/s, retry 0.1 s).
ServoConfig MissionServoDefaults();
/// The grasp sequence as the mission sets it.
GraspSequenceConfig MissionSequenceDefaults();

struct MissionConfig {
  std::string source;                       ///< the file (for messages)
  std::string world{"world_mission.yaml"};  ///< simulated world, resolved against the file's folder
  /// Perception settings (detection/perception_config.h), resolved against the
  /// file's folder; empty: the code's defaults.
  std::string perception;
  double takeoff_altitude_m{2.0};  ///< above the take-off point, [0.5, 20] m
  Eigen::Vector3d approach_w_m{2.70, 0.0,
                               -2.2};  ///< waypoint near the object (NED), each [-100, 100] m
  double yaw_rad{0.0};                 ///< heading held through the mission, [-pi, pi] rad
  /// Where the object should sit in the body frame while the arms grasp it
  /// (FRD: ahead, right, below), each [-1, 1] m: the centre of the placement
  /// search (`placement`), which the mission replaces by the placement found
  /// for its object and arms; the placement itself when the search is off.
  Eigen::Vector3d grasp_dto_m{0.075, 0.0, 0.47};
  double arrive_tolerance_m{0.15};  ///< a waypoint counts as reached within this, (0, 5] m
  /// Tracking never takes the vehicle farther than this from the approach
  /// waypoint, and an object seen farther than this from it is not followed, (0, 10] m.
  double tracking_radius_m{1.0};
  double lift_m{0.5};              ///< climb after the grasp, [0, 10] m
  double servo_rate_hz{100.0};     ///< arm servo loop, [10, 1000] Hz
  double setpoint_rate_hz{10.0};   ///< autopilot position setpoints, [2, 100] Hz
  double reevaluate_rate_hz{5.0};  ///< background grasp re-evaluation, (0, 100] Hz
  /// low-pass time constant of the tracked object position, (0, 10] s
  double object_filter_s{0.5};
  /// The autopilot's lag from a position setpoint to the vehicle there (its
  /// delay plus its response time), [0, 5] s: the tracking setpoint leads the
  /// object by its estimated velocity times this plus object_filter_s.
  double vehicle_lag_s{0.75};
  /// The estimate is moved on with its velocity to the present, at most this
  /// far ahead of its frame, [0, 1] s.
  double predict_max_s{0.2};
  /// While an attempt runs, the object's position along its length comes
  /// from its motion fitted over the frames of this long before the attempt
  /// (the fingers hide its ends), [0, 30] s; 0: from every frame.
  double length_fit_s{3.0};
  /// A frame this far from the fitted motion along the length disagrees with
  /// it, (0, 1] m; length_break_frames such frames in a row (the object
  /// stopped or turned) start a new fit from them, [1, 30].
  double length_break_m{0.02};
  int length_break_frames{3};
  /// Frames a refit of that motion needs once an attempt runs, [2, 300].
  int length_refit_frames{8};
  /// A free gripper that closed on nothing, across the carried object's
  /// length and this near one of its ends or nearer, moves the carried
  /// estimate along the length so that the end lies at the tool (the miss
  /// says the end lay short of it), [0, 0.2] m; 0: never.
  double empty_close_shift_max_m{0.05};
  /// at the waypoint without finding the object: give up, (0, 600] s
  double search_timeout_s{20.0};
  double timeout_s{180.0};       ///< the whole mission, (0, 3600] s
  double servo_margin_m{0.005};  ///< arms' clearance to the safe volume and each other, [0, 0.05] m

  PlacementConfig placement;                              ///< `placement`
  GraspPolicyConfig policy;                               ///< `policy`
  GraspPlannerConfig planner = MissionPlannerDefaults();  ///< `planner`
  /// `servo`; ik.tolerance is a 6-DoF arm's, servo_ik_tolerance_4dof a 4-DoF arm's.
  ServoConfig servo = MissionServoDefaults();
  /// `servo.ik_tolerance_4dof`: a 4-DoF arm's approach axis follows from the
  /// tool position, so the planned axis is met only within a few degrees when
  /// the object moves: position exactly, approach axis and roll nearly.
  PoseTolerance servo_ik_tolerance_4dof{1e-4, 0.10, 0.15};
  /// `grasp_sequence`; precatch_distance_m is the planner's, close_time_s the
  /// platform gripper's.
  GraspSequenceConfig grasp_sequence = MissionSequenceDefaults();

  /// Camera-to-arm calibrations written by `aerograsp calibrate`
  /// (calibration_<arm>.yaml), resolved against this file's folder; the arm's
  /// base is then dMc * cMb from the file instead of the platform's nominal
  /// mount. Empty: the nominal one.
  std::string calibration_left;
  std::string calibration_right;
  /// The files' cMb (the arm base in the camera frame), read by Load.
  std::optional<Eigen::Isometry3d> calibrated_cMb[2];

  /// The servo settings for an arm of `dof` joints.
  ServoConfig ServoFor(int dof) const;

  /// Reads a mission YAML; absent keys keep their defaults.
  /// @throws ConfigError "<file>: <key>: ..." for unknown keys, wrong types or values out of range.
  static MissionConfig Load(const std::string& path);
  /// `source` is the file (Load passes `this->source`), `prefix` the key path
  /// of this tree in it, ending in "." ("" at the top). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound; for a calibration file
  /// "<file>: calibration_left: <calibration file>: <key>: ..." (missing,
  /// malformed, not a rigid transform, or of the other arm).
  void Validate(const std::string& source, const std::string& prefix) const;
  /// Every setting as YAML that Load reads back to the same values (paths as they are).
  std::string ToYaml() const;
};

}  // namespace aerograsp
