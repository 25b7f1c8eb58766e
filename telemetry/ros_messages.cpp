#include "telemetry/ros_messages.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include "telemetry/cdr_writer.h"

namespace aerograsp {
namespace {

// The .msg texts (ROS 2 Humble), by "package/Type".
const std::map<std::string, std::string>& Definitions() {
  static const std::map<std::string, std::string> defs = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"std_msgs/Bool", "bool data\n"},
      {"std_msgs/String", "string data\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/Pose", "Point position\nQuaternion orientation\n"},
      {"geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/PoseWithCovarianceStamped",
       "std_msgs/Header header\nPoseWithCovariance pose\n"},
      {"geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"sensor_msgs/JointState",
       "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\n"
       "float64[] effort\n"},
      {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
      {"sensor_msgs/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
       "uint32 step\nuint8[] data\n"},
      {"sensor_msgs/RegionOfInterest",
       "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"},
      {"sensor_msgs/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
       "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
       "uint32 binning_y\nRegionOfInterest roi\n"},
      {"rcl_interfaces/Log",
       "byte DEBUG=10\nbyte INFO=20\nbyte WARN=30\nbyte ERROR=40\nbyte FATAL=50\n"
       "builtin_interfaces/Time stamp\nuint8 level\nstring name\nstring msg\nstring file\n"
       "string function\nuint32 line\n"},
  };
  return defs;
}

// Each type's dependencies, in the order they are appended.
const std::map<std::string, std::vector<std::string>>& Dependencies() {
  static const std::vector<std::string> header = {"std_msgs/Header", "builtin_interfaces/Time"};
  const auto with_header = [](std::vector<std::string> more) {
    std::vector<std::string> all = header;
    all.insert(all.end(), more.begin(), more.end());
    return all;
  };
  static const std::map<std::string, std::vector<std::string>> deps = {
      {"geometry_msgs/PoseWithCovarianceStamped",
       with_header({"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose", "geometry_msgs/Point",
                    "geometry_msgs/Quaternion"})},
      {"sensor_msgs/JointState", header},
      {"tf2_msgs/TFMessage",
       {"geometry_msgs/TransformStamped", "std_msgs/Header", "builtin_interfaces/Time",
        "geometry_msgs/Transform", "geometry_msgs/Vector3", "geometry_msgs/Quaternion"}},
      {"sensor_msgs/CompressedImage", header},
      {"sensor_msgs/Image", header},
      {"sensor_msgs/CameraInfo", with_header({"sensor_msgs/RegionOfInterest"})},
      {"rcl_interfaces/Log", {"builtin_interfaces/Time"}},
      {"std_msgs/Bool", {}},
      {"std_msgs/String", {}},
  };
  return deps;
}

void Header(CdrWriter* w, double t_s, const std::string& frame_id) {
  std::int32_t sec;
  std::uint32_t nanosec;
  RosTime(t_s, &sec, &nanosec);
  w->Int32(sec);
  w->UInt32(nanosec);
  w->String(frame_id);
}

void PoseFields(CdrWriter* w, const Eigen::Isometry3d& aMb) {
  const Eigen::Vector3d p = aMb.translation();
  const Eigen::Quaterniond q(aMb.rotation());
  w->Float64(p.x());
  w->Float64(p.y());
  w->Float64(p.z());
  w->Float64(q.x());
  w->Float64(q.y());
  w->Float64(q.z());
  w->Float64(q.w());
}

}  // namespace

std::string Ros2MsgDefinition(const std::string& type) {
  // "pkg/msg/Type" -> "pkg/Type"
  const std::size_t first = type.find('/'), last = type.rfind('/');
  const std::string key =
      first == last ? type : type.substr(0, first) + "/" + type.substr(last + 1);
  const auto deps = Dependencies().find(key);
  if (deps == Dependencies().end())
    throw std::invalid_argument("no ROS 2 definition for '" + type + "'");
  std::string text = Definitions().at(key);
  for (const std::string& dep : deps->second) {
    text += std::string(80, '=') + "\nMSG: " + dep + "\n" + Definitions().at(dep);
  }
  return text;
}

void RosTime(double t_s, std::int32_t* sec, std::uint32_t* nanosec) {
  const std::int64_t ns = t_s > 0 ? std::llround(t_s * 1e9) : 0;
  *sec = static_cast<std::int32_t>(ns / 1000000000);
  *nanosec = static_cast<std::uint32_t>(ns % 1000000000);
}

std::vector<std::uint8_t> EncodePoseWithCovarianceStamped(const TelemetryObjectPose& pose) {
  CdrWriter w;
  Header(&w, pose.t_s, pose.frame_id);
  PoseFields(&w, pose.fMo);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) w.Float64(pose.covariance ? (*pose.covariance)(r, c) : 0.0);
  }
  return w.Take();
}

std::vector<std::uint8_t> EncodeJointState(const TelemetryArms& arms, bool targets) {
  std::vector<std::string> names;
  std::vector<double> q, v;
  bool velocities = !targets;
  for (const TelemetryArmState& arm : arms.arms) {
    velocities = velocities && arm.velocity_radps.size() == arm.position_rad.size() &&
                 arm.position_rad.size() > 0;
  }
  for (const TelemetryArmState& arm : arms.arms) {
    const Eigen::VectorXd& values = targets ? arm.target_rad : arm.position_rad;
    if (values.size() == 0) continue;
    const std::string prefix = "arm_" + arm.arm + "_";
    for (Eigen::Index j = 0; j < values.size(); ++j) {
      names.push_back(prefix + (j < static_cast<Eigen::Index>(arm.joint_names.size())
                                    ? arm.joint_names[j]
                                    : "j" + std::to_string(j)));
      q.push_back(values[j]);
      if (velocities) v.push_back(arm.velocity_radps[j]);
    }
    if (targets) continue;
    names.push_back(prefix + "gripper");
    q.push_back(arm.gripper_aperture_m);
    if (velocities) v.push_back(NAN);
  }
  CdrWriter w;
  Header(&w, arms.t_s, "");
  w.StringSequence(names);
  w.Float64Sequence(q);
  w.Float64Sequence(v);
  w.Float64Sequence({});
  return w.Take();
}

std::vector<std::uint8_t> EncodeTfMessage(double t_s,
                                          const std::vector<TelemetryTransform>& transforms) {
  CdrWriter w;
  w.SequenceLength(transforms.size());
  for (const TelemetryTransform& t : transforms) {
    Header(&w, t_s, t.parent);
    w.String(t.child);
    PoseFields(&w, t.parentMchild);
  }
  return w.Take();
}

std::vector<std::uint8_t> EncodeCompressedImage(double t_s, const std::string& frame_id,
                                                const std::string& format,
                                                const std::vector<std::uint8_t>& data) {
  CdrWriter w;
  Header(&w, t_s, frame_id);
  w.String(format);
  w.ByteSequence(data.data(), data.size());
  return w.Take();
}

std::vector<std::uint8_t> EncodeDepthImage(double t_s, const std::string& frame_id,
                                           const DepthImage& depth) {
  CdrWriter w;
  Header(&w, t_s, frame_id);
  w.UInt32(static_cast<std::uint32_t>(depth.height));
  w.UInt32(static_cast<std::uint32_t>(depth.width));
  w.String("16UC1");
  w.UInt8(0);  // little-endian
  w.UInt32(static_cast<std::uint32_t>(depth.width * 2));
  w.SequenceLength(depth.data.size() * 2);
  for (std::uint16_t d : depth.data) {
    w.UInt8(static_cast<std::uint8_t>(d & 0xff));
    w.UInt8(static_cast<std::uint8_t>(d >> 8));
  }
  return w.Take();
}

std::vector<std::uint8_t> EncodeCameraInfo(double t_s, const std::string& frame_id,
                                           const CameraIntrinsics& K) {
  CdrWriter w;
  Header(&w, t_s, frame_id);
  w.UInt32(static_cast<std::uint32_t>(K.height));
  w.UInt32(static_cast<std::uint32_t>(K.width));
  w.String("plumb_bob");
  w.Float64Sequence({0.0, 0.0, 0.0, 0.0, 0.0});
  for (double v : {K.fx, 0.0, K.cx, 0.0, K.fy, K.cy, 0.0, 0.0, 1.0}) w.Float64(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) w.Float64(v);
  for (double v : {K.fx, 0.0, K.cx, 0.0, 0.0, K.fy, K.cy, 0.0, 0.0, 0.0, 1.0, 0.0}) w.Float64(v);
  w.UInt32(0);  // binning
  w.UInt32(0);
  for (int k = 0; k < 4; ++k) w.UInt32(0);  // roi: the full image
  w.Bool(false);
  return w.Take();
}

std::vector<std::uint8_t> EncodeLog(double t_s, TelemetryLevel level, const std::string& name,
                                    const std::string& text) {
  CdrWriter w;
  std::int32_t sec;
  std::uint32_t nanosec;
  RosTime(t_s, &sec, &nanosec);
  w.Int32(sec);
  w.UInt32(nanosec);
  w.UInt8(static_cast<std::uint8_t>(10 * (static_cast<int>(level) + 1)));
  w.String(name);
  w.String(text);
  w.String("");  // file
  w.String("");  // function
  w.UInt32(0);   // line
  return w.Take();
}

std::vector<std::uint8_t> EncodeBool(bool value) {
  CdrWriter w;
  w.Bool(value);
  return w.Take();
}

std::vector<std::uint8_t> EncodeString(const std::string& value) {
  CdrWriter w;
  w.String(value);
  return w.Take();
}

}  // namespace aerograsp
