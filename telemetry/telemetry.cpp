#include "telemetry/telemetry.h"

namespace aerograsp {

void FanOutSink::Add(std::unique_ptr<TelemetrySink> sink) {
  if (sink) sinks_.push_back(std::move(sink));
}

void FanOutSink::StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) {
  for (auto& s : sinks_) s->StaticTransforms(t_s, transforms);
}

void FanOutSink::Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) {
  for (auto& s : sinks_) s->Transforms(t_s, transforms);
}

void FanOutSink::ObjectPose(const TelemetryObjectPose& pose) {
  for (auto& s : sinks_) s->ObjectPose(pose);
}

void FanOutSink::Arms(const TelemetryArms& arms) {
  for (auto& s : sinks_) s->Arms(arms);
}

void FanOutSink::Transition(const TelemetryTransition& transition) {
  for (auto& s : sinks_) s->Transition(transition);
}

void FanOutSink::GraspPair(const TelemetryGraspPair& pair) {
  for (auto& s : sinks_) s->GraspPair(pair);
}

void FanOutSink::Image(const TelemetryImage& image) {
  for (auto& s : sinks_) s->Image(image);
}

void FanOutSink::Log(double t_s, TelemetryLevel level, const std::string& name,
                     const std::string& line) {
  for (auto& s : sinks_) s->Log(t_s, level, name, line);
}

void FanOutSink::Close() {
  for (auto& s : sinks_) s->Close();
}

Eigen::Isometry3d MapMWorld() {
  Eigen::Isometry3d mapMw = Eigen::Isometry3d::Identity();
  mapMw.linear() << 0, 1, 0,  //
      1, 0, 0,                //
      0, 0, -1;
  return mapMw;
}

void EmergencyStopLatch::Request(const std::string& source, const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (requested_) return;
  requested_ = true;
  source_ = source;
  reason_ = reason;
}

void EmergencyStopLatch::Note(const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  notes_.push_back(line);
}

EmergencyStopPoll EmergencyStopLatch::Poll(double /*t_s*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  EmergencyStopPoll poll;
  poll.stop = requested_;
  poll.source = source_;
  poll.reason = reason_;
  poll.notes.swap(notes_);
  return poll;
}

}  // namespace aerograsp
