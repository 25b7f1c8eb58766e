// The telemetry written to an MCAP file (telemetry/mcap_writer.h) with ROS 2
// schemas (`ros2msg`) and CDR messages (telemetry/ros_messages.h, the topics of
// ros_topic), so Foxglove and the ROS 2 tools (ros2 bag with its MCAP plugin)
// open it. Log times are the telemetry's t_s in nanoseconds.
//
// What is kept (McapConfig): every object pose, transition, grasp pair and
// log line; the arms and each set of moving transforms at state_rate_hz; the camera at
// image_rate_hz (JPEG, with its CameraInfo; depth as 16UC1 when asked).
// A write that fails (a full disk) is said once through `note`; the run goes
// on without the log, and the file keeps its complete chunks.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "telemetry/mcap_writer.h"
#include "telemetry/telemetry.h"
#include "telemetry/telemetry_config.h"

namespace aerograsp {

class McapSink final : public TelemetrySink {
 public:
  /// Creates `path`. `note` (kept) receives one line when writing fails.
  /// @throws std::runtime_error naming the path when it cannot be created.
  McapSink(const std::string& path, const McapConfig& config,
           std::function<void(const std::string&)> note);
  ~McapSink() override;

  void StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) override;
  void Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) override;
  void ObjectPose(const TelemetryObjectPose& pose) override;
  void Arms(const TelemetryArms& arms) override;
  void Transition(const TelemetryTransition& transition) override;
  void GraspPair(const TelemetryGraspPair& pair) override;
  void Image(const TelemetryImage& image) override;
  void Log(double t_s, TelemetryLevel level, const std::string& name,
           const std::string& line) override;
  void Close() override;

  const McapWriter& writer() const { return writer_; }

 private:
  /// The channel of `topic` (created with its schema at first use).
  std::uint16_t Channel(const std::string& topic, const std::string& type);
  void Put(const std::string& topic, const std::string& type, double t_s,
           const std::vector<std::uint8_t>& data);
  std::string FailureLine() const;
  /// True when `t_s` is at least one period after the last kept one.
  static bool Due(double t_s, double rate_hz, double* last_s);

  McapConfig config_;
  std::function<void(const std::string&)> note_;
  McapWriter writer_;
  bool reported_ = false;
  std::map<std::string, std::uint16_t> schemas_, channels_;
  double last_image_s_ = -1e300, last_arms_s_ = -1e300;
  std::map<std::string, double> last_tf_s_;  // by the transforms' child frames
};

}  // namespace aerograsp
