// aerograsp on ROS 2's wire: the telemetry (telemetry/telemetry.h) published
// as ROS 2 topics over DDS (Cyclone DDS, with ROS 2's names, types and QoS, so
// `ros2 topic echo`, RViz and Foxglove see them without a bridge node), and
// the emergency stops heard on a std_msgs/Bool topic. docs/ros2.md lists every
// topic with its type, QoS and frames.
//
// Settings: Ros2Config (telemetry/telemetry_config.h). On the wire (NS:
// Ros2Config::topic_namespace, "aerograsp" by default):
//   /NS/object_pose             geometry_msgs/PoseStamped            sensor data QoS
//   /NS/object_pose_covariance  geometry_msgs/PoseWithCovarianceStamped  sensor data QoS
//   /NS/object_found            std_msgs/Bool                        reliable, keep last 10
//   /NS/joint_states            sensor_msgs/JointState (measured)    reliable, keep last 10
//   /NS/joint_targets           sensor_msgs/JointState (commanded)   reliable, keep last 10
//   /tf                         tf2_msgs/TFMessage                   reliable, keep last 100
//   /tf_static                  tf2_msgs/TFMessage                   reliable, transient local, 1
//   /NS/transitions             std_msgs/String                      reliable, keep last 10
//   /NS/grasp_pair              std_msgs/String                      reliable, transient local, 1
//   /diagnostics                diagnostic_msgs/DiagnosticArray      reliable, keep last 10
//   /rosout                     rcl_interfaces/Log                   reliable, transient local,
//   1000 /NS/camera/color/image_raw, /NS/camera/depth/image_raw  sensor_msgs/Image  sensor data QoS
//   /NS/camera/color/camera_info  sensor_msgs/CameraInfo             sensor data QoS
//   /clock                      rosgraph_msgs/Clock                  best effort, keep last 1
//   /NS/emergency_stop (heard)     std_msgs/Bool                        reliable, keep last 10
// Stamps: the command's start on the wall clock plus mission time (so, in
// simulation, /clock runs ahead of the wall clock as the mission does).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "telemetry/telemetry.h"
#include "telemetry/telemetry_config.h"

namespace aerograsp {

class Ros2Participant;

/// What OpenRos2 gives a command.
struct Ros2Bridge {
  /// Publishes every call on the topics above; never blocks the caller for a
  /// subscriber (a reliable topic whose subscriber does not acknowledge drops
  /// messages, said once per topic).
  std::unique_ptr<TelemetrySink> sink;
  /// true on /NS/emergency_stop requests a stop (latched; false is ignored);
  /// malformed or mistyped messages are reported in the poll's notes.
  std::unique_ptr<EmergencyStopSource> emergency_stop;
  /// The DDS participant both share (for WaitForSubscribers).
  std::shared_ptr<Ros2Participant> participant;
  explicit operator bool() const { return sink != nullptr; }
};

/// Joins DDS domain `config.domain_id` and creates the topics; with
/// `config.emergency_stop_wait_s` > 0 waits that long at most for a publisher
/// of the emergency stop (said through `note` when none came). When
/// `config.enabled` is false, returns an empty bridge and opens nothing. When
/// DDS cannot start (no usable interface, a bad DDS configuration), says so
/// through `note` once and returns an empty bridge: the command goes on
/// without ROS 2. The sink calls `note` from the caller's thread only (what
/// DDS's own threads see is said at the sink's next call).
/// @param start_wall_s the command's start, seconds since the Unix epoch
///   (the stamps' origin); < 0: now.
Ros2Bridge OpenRos2(const Ros2Config& config, std::function<void(const std::string&)> note,
                    double start_wall_s = -1.0);

/// Waits until each topic the bridge writes has at least `count` subscribers
/// (a command that must not start before a listener is there; the tests).
/// @returns false after `timeout_s` s without them, or for an empty bridge.
bool WaitForSubscribers(const Ros2Bridge& bridge, int count, double timeout_s);

}  // namespace aerograsp
