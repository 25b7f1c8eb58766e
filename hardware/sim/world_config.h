// Configuration of the simulated world (data/config/world_default.yaml is the
// reference): the scene, the object and its motion, the vehicle's hover
// behaviour, the arms' servo dynamics, and the camera. World frame w is NED
// with its origin on the ground at the take-off point.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "hardware/sim/d435_model.h"

namespace aerograsp {

struct SceneConfig {
  /// centre of the support pipe's axis (NED, so z < 0 is up)
  Eigen::Vector3d pipe_center_w_m{0.0, 0.0, -1.3};
  double pipe_yaw_rad{M_PI / 2};  ///< pipe axis heading from north, [-pi, pi] rad (pi/2: east-west)
  double pipe_radius_m{0.08};     ///< (0, 1] m
  double pipe_length_m{4.0};      ///< (0, 50] m
  int clutter_count{14};          ///< boxes and cylinders on the ground, [0, 200]
  /// clutter lies within this distance of the pipe centre, (0, 50] m
  double clutter_radius_m{5.0};
  double ground_tile_m{0.5};  ///< size of the ground texture's tiles, (0, 10] m
};

/// How the object moves: along the top of the pipe.
struct ObjectMotionConfig {
  std::string name{"crawler"};     ///< a shipped object name or a model path (core/object_model.h)
  std::string motion{"static"};    ///< "static" | "crawl" (back and forth along the pipe)
  double start_along_pipe_m{0.0};  ///< position along the pipe axis from its centre, m
  double speed_mps{0.03};          ///< crawl speed, [0, 1] m/s
  double travel_m{0.4};         ///< crawl from start to start + travel and back, [0, pipe length] m
  double yaw_on_pipe_rad{0.0};  ///< object x from the pipe axis, about the vertical, rad
  /// At this simulated time the object, unless a gripper holds it, is knocked
  /// off the pipe onto the ground beside it, [-1, 1e6] s; < 0: never.
  double knocked_off_at_s{-1.0};
};

struct VehicleSimConfig {
  /// "hover" (at start_w_m, flying) | "ground" (disarmed at the origin)
  std::string start{"hover"};
  Eigen::Vector3d start_w_m{-0.26, -0.15, -2.104};     ///< hover start (NED), m
  double start_yaw_rad{0.0};                           ///< heading, rad
  Eigen::Vector3d sway_amplitude_m{0.03, 0.03, 0.02};  ///< per axis, each [0, 1] m
  Eigen::Vector3d sway_frequency_hz{0.31, 0.23, 0.4};  ///< per axis, each [0, 5] Hz
  double tilt_amplitude_rad{0.02};                     ///< roll and pitch sway, [0, 0.3] rad
  double gust_rate_hz{0.1};                            ///< mean gusts per second, [0, 10]
  double gust_speed_mps{0.15};                         ///< velocity kick of a gust, [0, 5] m/s
  double drift_std_m{0.02};           ///< stationary spread of the slow drift, [0, 1] m
  double drift_time_constant_s{8.0};  ///< correlation time of the drift, (0, 1000] s
  double response_time_s{0.6};     ///< first-order time constant of setpoint following, (0, 10] s
  double delay_s{0.15};            ///< setpoint-to-response delay (PX4: ~150 ms), [0, 2] s
  double max_speed_mps{1.0};       ///< (0, 20] m/s
  double offboard_timeout_s{0.5};  ///< no setpoint for this long in offboard: hold, (0, 10] s
  double landed_height_m{0.30};    ///< body origin above the ground when landed, [0, 2] m
};

struct ArmsSimConfig {
  double lag_s{0.05};         ///< servo first-order lag, (0, 2] s
  double speed_scale{1.0};    ///< fraction of the URDF velocity limits the servos reach, (0, 2]
  int position_counts{1024};  ///< position resolution (SCS: 10 bits), [2, 65536]
  /// angle spanned by the counts (SCS: about +-110 deg), (0, 360] deg
  double position_range_deg{220.0};
};

struct CameraSimConfig {
  double frame_rate_hz{30.0};  ///< (0, 300] Hz
  /// Image size relative to the platform's camera XML: 1, or 0.5 for the D435's
  /// 320x240 colour stream with depth aligned to it (intrinsics halved).
  double image_scale{1.0};
  D435Config d435;
  double light_azimuth_deg{30.0};    ///< direction towards the sun, from north, deg
  double light_elevation_deg{55.0};  ///< above the horizon, (0, 90] deg
  double light_intensity{0.8};       ///< [0, 2]
  double ambient{0.35};              ///< [0, 1]
  double light_variation{0.1};       ///< slow relative change of the intensity, [0, 0.5]
};

/// A dark panel that passes between the camera and the object and hides it
/// fully for a while (the "re-acquired after being hidden" test). Off unless
/// the world file has an `occluder` section.
struct OccluderConfig {
  bool enabled{false};
  double start_s{2.0};     ///< first time it hides the object, simulated s, [0, 1e6]
  double duration_s{1.0};  ///< how long each time, (0, 1e6] s
  double period_s{0.0};    ///< hides again every period (0: once), 0 or > duration_s, s
  /// from the camera along the line to the object, [0.2, 2] m (the D435 sees from 0.2 m)
  double distance_m{0.3};
  double size_m{0.35};  ///< side of the square panel, (0, 5] m
};

struct WorldConfig {
  std::string source;                          ///< file it was read from (for messages)
  std::string platform{"platform_4dof.yaml"};  ///< platform YAML, relative to this file's folder
  double physics_step_s{0.002};                ///< integration step, (0, 0.05] s
  SceneConfig scene;
  ObjectMotionConfig object;
  VehicleSimConfig vehicle;
  ArmsSimConfig arms;
  CameraSimConfig camera;
  OccluderConfig occluder;

  /// @throws ConfigError "<file>: <key>: ..." for a missing file, an unknown
  /// key, a wrong type or a value out of range.
  static WorldConfig Load(const std::string& path);
  /// `source` is the file (Load passes `this->source`), `prefix` the key path
  /// of this tree in it, ending in "." ("" at the top). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

}  // namespace aerograsp
