// Settings of the telemetry a command writes or publishes
// (data/config/telemetry.yaml; each field's unit and range there and here).
#pragma once

#include <string>

namespace aerograsp {

/// The MCAP log written beside a command's report (telemetry/mcap_sink.h).
struct McapConfig {
  bool enabled = true;  ///< write DIR/<command>.mcap
  /// Camera frames kept per second of mission time, (0, 60]; the others are
  /// skipped (the images are most of the file).
  double image_rate_hz = 5.0;
  int jpeg_quality = 75;  ///< [10, 100], OpenCV's IMWRITE_JPEG_QUALITY
  bool depth = false;     ///< also the depth images (raw 16UC1), about 600 kB each uncompressed
  /// Arms and moving transforms kept per second of mission time, (0, 1000];
  /// at or above the servo rate every cycle is kept.
  double state_rate_hz = 50.0;
  std::string compression = "zstd";  ///< chunk compression: "none" | "lz4" | "zstd"
  int chunk_size_kib = 1024;         ///< a chunk is closed past this much data, [16, 65536] KiB
};

/// ROS 2 topics over DDS (ros2/ros2_bridge.h, docs/ros2.md): whether a
/// command joins a DDS domain, which one, under which namespace, and how often
/// the high-rate topics go out. The commands' --ros2 and --ros2-domain
/// override `enabled` and `domain_id`.
struct Ros2Config {
  bool enabled = false;  ///< join the domain, publish, hear the emergency stop
  int domain_id = 0;     ///< ROS_DOMAIN_ID, [0, 232]
  /// Prefix of aerograsp's own topics ("aerograsp" -> /aerograsp/joint_states;
  /// DDS topic rt/aerograsp/joint_states). Letters, digits, '_' and '/', no
  /// leading digit or '/', no trailing '/'. /tf, /tf_static, /clock,
  /// /diagnostics and /rosout are ROS's global names and never prefixed.
  std::string topic_namespace = "aerograsp";
  /// A Cyclone DDS XML configuration file for the participant (what a
  /// CYCLONEDDS_URI would name); empty: CYCLONEDDS_URI from the environment,
  /// else Cyclone's defaults (the first multicast-capable interface).
  std::string dds_config;
  /// Joints, targets, /tf and /clock at most this often, Hz of mission time, (0, 1000].
  double joint_states_rate_hz = 100.0;
  /// colour, depth and camera_info, Hz of mission time, [0, 60]; 0: none
  double image_rate_hz = 5.0;
  bool publish_clock = true;  ///< /clock with the stamps (mission time in simulation)
  /// At the start, wait up to this long for a publisher on /NS/emergency_stop
  /// before anything moves (said when none came), s, [0, 600]; 0: no wait.
  double emergency_stop_wait_s = 0.0;
};

struct TelemetryConfig {
  std::string source;  ///< the file it was read from (for messages)
  McapConfig mcap;
  Ros2Config ros2;

  /// Reads and validates `path`.
  /// @throws ConfigError naming the file, the key and the bound.
  static TelemetryConfig Load(const std::string& path);
  /// `source` is the file (Load passes `this->source`), `prefix` the key path
  /// of this tree in it, ending in "." ("" at the top). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

}  // namespace aerograsp
