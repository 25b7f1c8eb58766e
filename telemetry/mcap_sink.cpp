#include "telemetry/mcap_sink.h"

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "telemetry/ros_messages.h"

namespace aerograsp {
namespace {

McapWriterOptions WriterOptions(const McapConfig& config) {
  McapWriterOptions o;
  o.profile = "ros2";
  o.library = "aerograsp";
  o.compression = config.compression;
  o.chunk_size_bytes = static_cast<std::size_t>(config.chunk_size_kib) * 1024;
  return o;
}

/// The QoS a ROS 2 publisher of the topic offers, as rosbag2 writes it in
/// the channel's `offered_qos_profiles` (rmw enums: history 1 keep last,
/// reliability 1 reliable, durability 1 transient local / 2 volatile).
std::string OfferedQos(const std::string& topic) {
  const bool latched = topic == ros_topic::kTfStatic;
  return std::string("- history: 1\n  depth: ") + (latched ? "1" : "10") +
         "\n  reliability: 1\n  durability: " + (latched ? "1" : "2") +
         "\n  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n"
         "  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n"
         "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 2147483647\n"
         "    nsec: 4294967295\n  avoid_ros_namespace_conventions: false";
}

std::uint64_t Nanoseconds(double t_s) {
  return t_s > 0 ? static_cast<std::uint64_t>(std::llround(t_s * 1e9)) : 0;
}

}  // namespace

McapSink::McapSink(const std::string& path, const McapConfig& config,
                   std::function<void(const std::string&)> note)
    : config_(config), note_(std::move(note)), writer_(path, WriterOptions(config)) {}

McapSink::~McapSink() = default;

bool McapSink::Due(double t_s, double rate_hz, double* last_s) {
  // A thousandth of a period early still counts (rounding of the callers' clocks).
  if (t_s - *last_s < 0.999 / rate_hz) return false;
  *last_s = t_s;
  return true;
}

std::uint16_t McapSink::Channel(const std::string& topic, const std::string& type) {
  const auto found = channels_.find(topic);
  if (found != channels_.end()) return found->second;
  auto schema = schemas_.find(type);
  if (schema == schemas_.end()) {
    schema =
        schemas_.emplace(type, writer_.AddSchema(type, "ros2msg", Ros2MsgDefinition(type))).first;
  }
  const std::uint16_t id = writer_.AddChannel(schema->second, topic, "cdr",
                                              {{"offered_qos_profiles", OfferedQos(topic)}});
  channels_.emplace(topic, id);
  return id;
}

void McapSink::Put(const std::string& topic, const std::string& type, double t_s,
                   const std::vector<std::uint8_t>& data) {
  if (writer_.failed()) return;
  const std::uint64_t ns = Nanoseconds(t_s);
  writer_.Write(Channel(topic, type), ns, ns, data);
  if (writer_.failed() && !reported_) {
    reported_ = true;
    if (note_) note_(FailureLine());
  }
}

std::string McapSink::FailureLine() const {
  char size[32];
  std::snprintf(size, sizeof size, "%.1f", writer_.bytes_written() / 1e6);
  return "the MCAP log stopped: " + writer_.error() + "; its first " + size +
         " MB (complete chunks, no summary) stay readable; the run goes on without it";
}

void McapSink::StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) {
  Put(ros_topic::kTfStatic, ros_type::kTfMessage, t_s, EncodeTfMessage(t_s, transforms));
}

void McapSink::Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) {
  std::string children;  // each set of frames keeps its own rate (a rare one is never dropped)
  for (const TelemetryTransform& t : transforms) children += t.child + ' ';
  auto last = last_tf_s_.emplace(children, -1e300).first;
  if (!Due(t_s, config_.state_rate_hz, &last->second)) return;
  Put(ros_topic::kTf, ros_type::kTfMessage, t_s, EncodeTfMessage(t_s, transforms));
}

void McapSink::ObjectPose(const TelemetryObjectPose& pose) {
  Put(ros_topic::kObjectFound, ros_type::kBool, pose.t_s, EncodeBool(pose.found));
  if (pose.valid) {
    Put(ros_topic::kObjectPose, ros_type::kPoseWithCovarianceStamped, pose.t_s,
        EncodePoseWithCovarianceStamped(pose));
  }
}

void McapSink::Arms(const TelemetryArms& arms) {
  if (!Due(arms.t_s, config_.state_rate_hz, &last_arms_s_)) return;
  Put(ros_topic::kJointStates, ros_type::kJointState, arms.t_s, EncodeJointState(arms, false));
  if (arms.arms[0].target_rad.size() > 0 || arms.arms[1].target_rad.size() > 0)
    Put(ros_topic::kJointTargets, ros_type::kJointState, arms.t_s, EncodeJointState(arms, true));
}

void McapSink::Transition(const TelemetryTransition& t) {
  Put(ros_topic::kTransitions, ros_type::kString, t.t_s,
      EncodeString(t.machine + ": " + t.from + " -> " + t.to + ": " + t.cause));
  Put(ros_topic::kLog, ros_type::kLog, t.t_s,
      EncodeLog(t.t_s, TelemetryLevel::kInfo, "aerograsp." + t.machine,
                t.from + " -> " + t.to + ": " + t.cause));
}

void McapSink::GraspPair(const TelemetryGraspPair& pair) {
  Put(ros_topic::kGraspPair, ros_type::kString, pair.t_s,
      EncodeString("left " + std::to_string(pair.left_pair) + " right " +
                   std::to_string(pair.right_pair) + ": " + pair.reason));
}

void McapSink::Image(const TelemetryImage& image) {
  if (!image.color || image.color->empty()) return;
  if (!Due(image.t_s, config_.image_rate_hz, &last_image_s_)) return;
  const ColorImage& rgb = *image.color;
  const cv::Mat rgb_mat(rgb.height, rgb.width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb_mat, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, config_.jpeg_quality});
  Put(ros_topic::kColorImage, ros_type::kCompressedImage, image.t_s,
      EncodeCompressedImage(image.t_s, image.frame_id, "jpeg", jpeg));
  Put(ros_topic::kCameraInfo, ros_type::kCameraInfo, image.t_s,
      EncodeCameraInfo(image.t_s, image.frame_id, image.K));
  if (config_.depth && image.depth && !image.depth->empty()) {
    Put(ros_topic::kDepthImage, ros_type::kImage, image.t_s,
        EncodeDepthImage(image.t_s, image.frame_id, *image.depth));
  }
}

void McapSink::Log(double t_s, TelemetryLevel level, const std::string& name,
                   const std::string& line) {
  Put(ros_topic::kLog, ros_type::kLog, t_s, EncodeLog(t_s, level, "aerograsp." + name, line));
}

void McapSink::Close() {
  const bool failed_before = writer_.failed();
  writer_.Close();
  if (writer_.failed() && !failed_before && !reported_) {
    reported_ = true;
    if (note_) note_(FailureLine());
  }
}

}  // namespace aerograsp
