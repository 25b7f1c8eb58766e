// Settings of the ROS 2 bridge (ros2/ros2_bridge.h): whether aerograsp joins a
// DDS domain, which one, under which namespace, and how often the high-rate
// topics go out. The `ros2:` section of the telemetry file
// (data/config/telemetry.yaml, or --telemetry); the commands' --ros2 and
// --ros2-domain override `enabled` and `domain_id`.
#pragma once

#include <string>

namespace aerograsp {

struct Ros2Config {
  std::string source = "ros2 settings";  ///< the file read, for messages (keys are under ros2.)
  bool enabled = false;                  ///< join the domain and publish (off: nothing is opened)
  int domain_id = 0;                     ///< ROS_DOMAIN_ID, [0, 232]
  /// Prefix of aerograsp's own topics ("aerograsp" -> /aerograsp/joint_states;
  /// DDS topic rt/aerograsp/joint_states). Letters, digits, '_' and '/', no
  /// leading or trailing '/'. /tf, /tf_static, /clock, /diagnostics and /rosout
  /// are ROS's global names and never prefixed.
  std::string topic_namespace = "aerograsp";
  /// A Cyclone DDS XML configuration file for the participant (what a
  /// CYCLONEDDS_URI would name); empty: CYCLONEDDS_URI from the environment,
  /// else Cyclone's defaults (the first multicast-capable interface).
  std::string dds_config;
  double joint_states_rate_hz =
      100;                    ///< Hz, (0, 1000]: joints, targets, /tf, /clock at most this often
  double image_rate_hz = 5;   ///< Hz, [0, 60]: colour, depth and camera_info; 0: none
  bool publish_clock = true;  ///< /clock with the stamps (mission time in simulation)

  /// @throws ConfigError naming the file and the key of the first bad value.
  void Validate() const;
  /// Reads the `ros2:` section of `path` (keys as the fields); a missing
  /// section or key keeps the defaults.
  /// @throws ConfigError for an unreadable file, an unknown key or a bad value.
  static Ros2Config Load(const std::string& path);
};

}  // namespace aerograsp
