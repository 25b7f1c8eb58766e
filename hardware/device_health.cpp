#include "hardware/device_health.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/config.h"

namespace aerograsp {

void DeviceHealthLimits::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& f = source;
  CheckRange(f, prefix + "servo_max_failed_reads", servo_max_failed_reads, 1, 100, "");
  CheckRange(f, prefix + "servo_max_reading_age_s", servo_max_reading_age_s, 0.005, 10.0, "s");
  CheckRange(f, prefix + "bus_max_error_rate", bus_max_error_rate, 0.0, 1.0, "");
  CheckRange(f, prefix + "bus_error_window_s", bus_error_window_s, 0.01, 10.0, "s");
  CheckRange(f, prefix + "bus_min_exchanges", bus_min_exchanges, 1, 10000, "");
  CheckRange(f, prefix + "servo_min_voltage_v", servo_min_voltage_v, 0.0, 30.0, "V");
  CheckRange(f, prefix + "servo_max_voltage_v", servo_max_voltage_v, servo_min_voltage_v, 30.0,
             "V");
  CheckRange(f, prefix + "servo_max_temperature_c", servo_max_temperature_c, 0.0, 120.0, "C");
  CheckRange(f, prefix + "autopilot_max_state_age_s", autopilot_max_state_age_s, 0.01, 60.0, "s");
  CheckRange(f, prefix + "camera_max_frame_age_s", camera_max_frame_age_s, 0.01, 10.0, "s");
  CheckRange(f, prefix + "camera_max_bad_depth_s", camera_max_bad_depth_s, 0.0, 10.0, "s");
}

const char* DeviceFaultKindName(DeviceFaultKind kind) {
  switch (kind) {
    case DeviceFaultKind::kServoSilent:
      return "servo_silent";
    case DeviceFaultKind::kServoStale:
      return "servo_stale";
    case DeviceFaultKind::kBusCorrupt:
      return "bus_corrupt";
    case DeviceFaultKind::kServoVoltage:
      return "servo_voltage";
    case DeviceFaultKind::kServoTemperature:
      return "servo_temperature";
    case DeviceFaultKind::kLinkLost:
      return "link_lost";
    case DeviceFaultKind::kCommandRejected:
      return "command_rejected";
    case DeviceFaultKind::kCameraNoFrame:
      return "camera_no_frame";
    case DeviceFaultKind::kCameraBadDepth:
      return "camera_bad_depth";
  }
  return "unknown";
}

std::vector<DeviceFault> CheckServo(const ScsServoStatus& servo, double reading_age_s,
                                    const DeviceHealthLimits& limits) {
  std::vector<DeviceFault> faults;
  const std::string device = fmt::format("servo {} (id {})", servo.name, servo.id);
  if (servo.failed_reads >= limits.servo_max_failed_reads) {
    faults.push_back({DeviceFaultKind::kServoSilent, device,
                      fmt::format("{} reads failed in a row (at most {})", servo.failed_reads,
                                  limits.servo_max_failed_reads - 1)});
  }
  if (reading_age_s > limits.servo_max_reading_age_s) {
    faults.push_back({DeviceFaultKind::kServoStale, device,
                      fmt::format("the newest position reading is {:.3f} s old (at most {:.3f} s)",
                                  reading_age_s, limits.servo_max_reading_age_s)});
  }
  if (servo.voltage_v > 0.0 && (servo.voltage_v < limits.servo_min_voltage_v ||
                                servo.voltage_v > limits.servo_max_voltage_v)) {
    faults.push_back({DeviceFaultKind::kServoVoltage, device,
                      fmt::format("supply {:.1f} V outside {:.1f}-{:.1f} V", servo.voltage_v,
                                  limits.servo_min_voltage_v, limits.servo_max_voltage_v)});
  }
  if (servo.temperature_c > limits.servo_max_temperature_c) {
    faults.push_back(
        {DeviceFaultKind::kServoTemperature, device,
         fmt::format("{} C, above {:.0f} C", servo.temperature_c, limits.servo_max_temperature_c)});
  }
  return faults;
}

std::optional<DeviceFault> CheckBusErrors(const BusCounters& from, const BusCounters& to,
                                          const DeviceHealthLimits& limits) {
  const std::int64_t exchanges = to.exchanges - from.exchanges;
  if (exchanges < limits.bus_min_exchanges) return std::nullopt;
  // A late reply is not corruption: its exchange timed out, which the
  // servo's failed reads count (CheckServo).
  const std::int64_t bad = to.bad_checksums - from.bad_checksums;
  const double rate = static_cast<double>(bad) / static_cast<double>(exchanges);
  if (rate <= limits.bus_max_error_rate) return std::nullopt;
  return DeviceFault{DeviceFaultKind::kBusCorrupt, "servo bus",
                     fmt::format("{} of the last {} replies corrupted ({:.1f} %, at most {:.1f} %)",
                                 bad, exchanges, 100.0 * rate, 100.0 * limits.bus_max_error_rate)};
}

std::optional<DeviceFault> CheckAutopilotLink(const VehicleState& state, double state_age_s,
                                              const DeviceHealthLimits& limits) {
  if (!state.link_ok) {
    return DeviceFault{DeviceFaultKind::kLinkLost, "autopilot", "the link is lost (no heartbeat)"};
  }
  if (state_age_s > limits.autopilot_max_state_age_s) {
    return DeviceFault{DeviceFaultKind::kLinkLost, "autopilot",
                       fmt::format("the newest vehicle state is {:.3f} s old (at most {:.3f} s)",
                                   state_age_s, limits.autopilot_max_state_age_s)};
  }
  return std::nullopt;
}

std::optional<DeviceFault> CheckCommandAnswer(const std::string& command, const CommandAck& ack,
                                              FlightMode mode) {
  if (ack.accepted || mode == FlightMode::kDisarmed || mode == FlightMode::kLanded)
    return std::nullopt;
  return DeviceFault{DeviceFaultKind::kCommandRejected, "autopilot",
                     "refused " + command + (ack.reason.empty() ? "" : ": " + ack.reason)};
}

std::vector<DeviceFault> CheckCamera(double frame_age_s, double bad_depth_for_s,
                                     const DeviceHealthLimits& limits) {
  std::vector<DeviceFault> faults;
  if (frame_age_s > limits.camera_max_frame_age_s) {
    faults.push_back({DeviceFaultKind::kCameraNoFrame, "camera",
                      fmt::format("no new frame for {:.3f} s (at most {:.3f} s)", frame_age_s,
                                  limits.camera_max_frame_age_s)});
  }
  if (bad_depth_for_s >= 0.0 && bad_depth_for_s >= limits.camera_max_bad_depth_s) {
    faults.push_back({DeviceFaultKind::kCameraBadDepth, "camera",
                      fmt::format("no valid depth pixel for {:.3f} s (at most {:.3f} s)",
                                  bad_depth_for_s, limits.camera_max_bad_depth_s)});
  }
  return faults;
}

bool DepthHasData(const DepthImage& depth) {
  return std::any_of(depth.data.begin(), depth.data.end(), [](std::uint16_t z) { return z != 0; });
}

// ---- DeviceHealth ---------------------------------------------------------------

std::vector<DeviceFault> DeviceHealth::Report(std::vector<DeviceFault> faults) {
  std::vector<DeviceFault> fresh;
  for (DeviceFault& f : faults) {
    if (!reported_.insert({f.device, f.kind}).second) continue;
    ++counts_[DeviceFaultKindName(f.kind)];
    fresh.push_back(std::move(f));
  }
  return fresh;
}

std::vector<DeviceFault> DeviceHealth::Servos(double now_s,
                                              const std::vector<ScsServoStatus>& servos,
                                              const BusCounters& counters) {
  std::vector<DeviceFault> faults;
  for (const ScsServoStatus& s : servos) {
    auto it = servo_reads_.find(s.id);
    if (it == servo_reads_.end() || it->second.first != s.good_reads) {
      servo_reads_[s.id] = {s.good_reads, now_s};
      it = servo_reads_.find(s.id);
    }
    for (DeviceFault& f : CheckServo(s, now_s - it->second.second, limits_))
      faults.push_back(std::move(f));
  }
  // The window: the oldest sample at least bus_error_window_s old is its start.
  bus_window_.emplace_back(now_s, counters);
  while (bus_window_.size() > 2 && now_s - bus_window_[1].first >= limits_.bus_error_window_s)
    bus_window_.pop_front();
  if (now_s - bus_window_.front().first >= limits_.bus_error_window_s) {
    if (auto f = CheckBusErrors(bus_window_.front().second, counters, limits_))
      faults.push_back(std::move(*f));
  }
  return Report(std::move(faults));
}

std::vector<DeviceFault> DeviceHealth::Autopilot(double now_s, const VehicleState& state) {
  if (!state_seen_ || state.stamp_s != state_stamp_s_) {
    state_seen_ = true;
    state_stamp_s_ = state.stamp_s;
    state_changed_s_ = now_s;
  }
  std::vector<DeviceFault> faults;
  if (auto f = CheckAutopilotLink(state, now_s - state_changed_s_, limits_))
    faults.push_back(std::move(*f));
  return Report(std::move(faults));
}

std::vector<DeviceFault> DeviceHealth::CommandAnswered(const std::string& command,
                                                       const CommandAck& ack, FlightMode mode) {
  std::vector<DeviceFault> faults;
  if (auto f = CheckCommandAnswer(command, ack, mode)) faults.push_back(std::move(*f));
  return Report(std::move(faults));
}

std::vector<DeviceFault> DeviceHealth::Frame(double now_s, double stamp_s, bool depth_has_data) {
  if (camera_idle_ || stamp_s > frame_stamp_s_) {
    if (camera_idle_) bad_depth_since_s_ = -1.0;
    camera_idle_ = false;
    frame_stamp_s_ = std::max(frame_stamp_s_, stamp_s);
    frame_new_s_ = now_s;
  }
  if (depth_has_data) {
    bad_depth_since_s_ = -1.0;
  } else if (bad_depth_since_s_ < 0.0) {
    bad_depth_since_s_ = now_s;
  }
  return Report(CheckCamera(now_s - frame_new_s_,
                            bad_depth_since_s_ < 0.0 ? -1.0 : now_s - bad_depth_since_s_, limits_));
}

}  // namespace aerograsp
