// ROS 2 messages in CDR (telemetry/cdr_writer.h) from the telemetry's own
// types, with their definitions as MCAP's `ros2msg` schema encoding wants
// them: the type's .msg text, then each type it uses after a line of 80 '='
// and "MSG: package/Type". Field layouts are those of ROS 2 (Humble and later).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "telemetry/telemetry.h"

namespace aerograsp {

/// The ROS 2 types the telemetry writes, by their full name
/// ("geometry_msgs/msg/PoseWithCovarianceStamped").
namespace ros_type {
inline constexpr const char* kPoseWithCovarianceStamped =
    "geometry_msgs/msg/PoseWithCovarianceStamped";
inline constexpr const char* kJointState = "sensor_msgs/msg/JointState";
inline constexpr const char* kTfMessage = "tf2_msgs/msg/TFMessage";
inline constexpr const char* kCompressedImage = "sensor_msgs/msg/CompressedImage";
inline constexpr const char* kImage = "sensor_msgs/msg/Image";
inline constexpr const char* kCameraInfo = "sensor_msgs/msg/CameraInfo";
inline constexpr const char* kLog = "rcl_interfaces/msg/Log";
inline constexpr const char* kBool = "std_msgs/msg/Bool";
inline constexpr const char* kString = "std_msgs/msg/String";
}  // namespace ros_type

/// The topics (ROS 2 names) the telemetry is written or published on.
namespace ros_topic {
inline constexpr const char* kTf = "/tf";               ///< TFMessage, moving frames
inline constexpr const char* kTfStatic = "/tf_static";  ///< TFMessage, fixed frames
/// PoseWithCovarianceStamped
inline constexpr const char* kObjectPose = "/aerograsp/object_pose_covariance";
inline constexpr const char* kObjectFound = "/aerograsp/object_found";    ///< Bool, each frame
inline constexpr const char* kJointStates = "/aerograsp/joint_states";    ///< JointState, both arms
inline constexpr const char* kJointTargets = "/aerograsp/joint_targets";  ///< JointState, commanded
/// String "machine: a -> b: why"
inline constexpr const char* kTransitions = "/aerograsp/transitions";
/// String "left L right R: why"
inline constexpr const char* kGraspPair = "/aerograsp/grasp_pair";
/// CompressedImage (JPEG)
inline constexpr const char* kColorImage = "/aerograsp/camera/color/image_raw/compressed";
inline constexpr const char* kCameraInfo = "/aerograsp/camera/color/camera_info";  ///< CameraInfo
inline constexpr const char* kDepthImage = "/aerograsp/camera/depth/image_raw";    ///< Image, 16UC1
inline constexpr const char* kLog = "/rosout";  ///< Log: log lines and state transitions
}  // namespace ros_topic

/// The `ros2msg` schema of one of the types above (the full name).
/// @throws std::invalid_argument for another name.
std::string Ros2MsgDefinition(const std::string& type);

/// builtin_interfaces/Time of `t_s` (negative: zero), nanoseconds rounded.
void RosTime(double t_s, std::int32_t* sec, std::uint32_t* nanosec);

/// geometry_msgs/PoseWithCovarianceStamped: the pose in pose.frame_id; the
/// covariance row-major, zeros when absent.
std::vector<std::uint8_t> EncodePoseWithCovarianceStamped(const TelemetryObjectPose& pose);
/// sensor_msgs/JointState of both arms, the joints named arm_left_j0 ...
/// arm_right_j3 (the arm's URDF names after "arm_<side>_"). Measured
/// (`targets` false): each arm's positions then its gripper as
/// arm_<side>_gripper (the aperture, m); velocities when every arm has them
/// (NaN for the grippers), else empty. Targets: the commanded joints only
/// (an arm without targets is left out). Efforts empty.
std::vector<std::uint8_t> EncodeJointState(const TelemetryArms& arms, bool targets);
/// tf2_msgs/TFMessage: one TransformStamped per transform, all stamped t_s.
std::vector<std::uint8_t> EncodeTfMessage(double t_s,
                                          const std::vector<TelemetryTransform>& transforms);
/// sensor_msgs/CompressedImage (`format`: "jpeg", "png").
std::vector<std::uint8_t> EncodeCompressedImage(double t_s, const std::string& frame_id,
                                                const std::string& format,
                                                const std::vector<std::uint8_t>& data);
/// sensor_msgs/Image of a depth image, encoding "16UC1" (little-endian).
std::vector<std::uint8_t> EncodeDepthImage(double t_s, const std::string& frame_id,
                                           const DepthImage& depth);
/// sensor_msgs/CameraInfo of a pinhole camera without distortion ("plumb_bob", d zeros).
std::vector<std::uint8_t> EncodeCameraInfo(double t_s, const std::string& frame_id,
                                           const CameraIntrinsics& K);
/// rcl_interfaces/Log (levels 10, 20, 30, 40, 50).
std::vector<std::uint8_t> EncodeLog(double t_s, TelemetryLevel level, const std::string& name,
                                    const std::string& text);
std::vector<std::uint8_t> EncodeBool(bool value);
std::vector<std::uint8_t> EncodeString(const std::string& value);

}  // namespace aerograsp
