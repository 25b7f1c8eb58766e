// The MAVLink messages the companion computer needs (docs/hardware.md, Autopilot),
// with their fields in wire order (by size, extensions last, as the MAVLink
// definitions lay them out). Each message lists its fields once, in Visit();
// Pack() and Unpack() serialise them little-endian. Unpack zero-fills what a
// truncated payload left out, as MAVLink 2 requires.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "hardware/mavlink/mavlink_codec.h"

namespace aerograsp {
namespace mavlink {

// Enumerations used (common.xml).
enum MavResult : std::uint8_t {
  kResultAccepted = 0,
  kResultTemporarilyRejected = 1,
  kResultDenied = 2,
  kResultUnsupported = 3,
  kResultFailed = 4,
  kResultInProgress = 5,
  kResultCancelled = 6,
};
const char* MavResultName(std::uint8_t result);
enum MavCmd : std::uint16_t {
  kCmdNavLand = 21,
  kCmdNavTakeoff = 22,
  kCmdDoSetMode = 176,
  kCmdComponentArmDisarm = 400,
};
constexpr std::uint8_t kModeFlagCustomModeEnabled = 1;
constexpr std::uint8_t kModeFlagSafetyArmed = 128;
enum LandedState : std::uint8_t {
  kLandedUndefined = 0,
  kLandedOnGround = 1,
  kLandedInAir = 2,
  kLandedTakeoff = 3,
  kLandedLanding = 4
};
constexpr std::uint8_t kFrameLocalNed = 1;  // MAV_FRAME_LOCAL_NED
/// POSITION_TARGET_TYPEMASK: use x, y, z and yaw only.
constexpr std::uint16_t kTypeMaskPositionYaw =
    0x0DF8;  // ignore vx..afz (bits 3-8) and yaw rate (bit 11)

// PX4 custom modes: main mode in bits 16-23, sub mode in 24-31 (px4_custom_mode.h).
namespace px4 {
constexpr std::uint8_t kMainAuto = 4;
constexpr std::uint8_t kMainOffboard = 6;
constexpr std::uint8_t kAutoTakeoff = 2;
constexpr std::uint8_t kAutoLoiter = 3;
constexpr std::uint8_t kAutoLand = 6;
inline std::uint32_t CustomMode(std::uint8_t main, std::uint8_t sub) {
  return (static_cast<std::uint32_t>(main) << 16) | (static_cast<std::uint32_t>(sub) << 24);
}
inline std::uint8_t MainMode(std::uint32_t custom_mode) { return (custom_mode >> 16) & 0xFF; }
inline std::uint8_t SubMode(std::uint32_t custom_mode) { return (custom_mode >> 24) & 0xFF; }
}  // namespace px4

struct Heartbeat {
  static constexpr std::uint32_t kId = 0;
  std::uint32_t custom_mode = 0;
  std::uint8_t type = 0, autopilot = 0, base_mode = 0, system_status = 0, mavlink_version = 3;
  template <class V>
  void Visit(V& v) {
    v(custom_mode), v(type), v(autopilot), v(base_mode), v(system_status), v(mavlink_version);
  }
};

struct SysStatus {
  static constexpr std::uint32_t kId = 1;
  std::uint32_t sensors_present = 0, sensors_enabled = 0, sensors_health = 0;
  std::uint16_t load = 0, voltage_battery = 0;
  std::int16_t current_battery = -1;
  std::uint16_t drop_rate_comm = 0, errors_comm = 0, errors_count1 = 0, errors_count2 = 0,
                errors_count3 = 0, errors_count4 = 0;
  std::int8_t battery_remaining = -1;
  std::uint32_t sensors_present_extended = 0, sensors_enabled_extended = 0,
                sensors_health_extended = 0;
  template <class V>
  void Visit(V& v) {
    v(sensors_present), v(sensors_enabled), v(sensors_health), v(load), v(voltage_battery),
        v(current_battery), v(drop_rate_comm), v(errors_comm), v(errors_count1), v(errors_count2),
        v(errors_count3), v(errors_count4), v(battery_remaining), v(sensors_present_extended),
        v(sensors_enabled_extended), v(sensors_health_extended);
  }
};

struct Attitude {
  static constexpr std::uint32_t kId = 30;
  std::uint32_t time_boot_ms = 0;
  float roll = 0, pitch = 0, yaw = 0, rollspeed = 0, pitchspeed = 0,
        yawspeed = 0;  ///< rad, rad/s (FRD body)
  template <class V>
  void Visit(V& v) {
    v(time_boot_ms), v(roll), v(pitch), v(yaw), v(rollspeed), v(pitchspeed), v(yawspeed);
  }
};

struct LocalPositionNed {
  static constexpr std::uint32_t kId = 32;
  std::uint32_t time_boot_ms = 0;
  float x = 0, y = 0, z = 0, vx = 0, vy = 0, vz = 0;  ///< m, m/s, NED
  template <class V>
  void Visit(V& v) {
    v(time_boot_ms), v(x), v(y), v(z), v(vx), v(vy), v(vz);
  }
};

struct CommandLong {
  static constexpr std::uint32_t kId = 76;
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0, param5 = 0, param6 = 0, param7 = 0;
  std::uint16_t command = 0;
  std::uint8_t target_system = 0, target_component = 0, confirmation = 0;
  template <class V>
  void Visit(V& v) {
    v(param1), v(param2), v(param3), v(param4), v(param5), v(param6), v(param7), v(command),
        v(target_system), v(target_component), v(confirmation);
  }
};

struct CommandAck {
  static constexpr std::uint32_t kId = 77;
  std::uint16_t command = 0;
  std::uint8_t result = 0;
  std::uint8_t progress = 0;                             // extension
  std::int32_t result_param2 = 0;                        // extension
  std::uint8_t target_system = 0, target_component = 0;  // extensions
  template <class V>
  void Visit(V& v) {
    v(command), v(result), v(progress), v(result_param2), v(target_system), v(target_component);
  }
};

struct SetPositionTargetLocalNed {
  static constexpr std::uint32_t kId = 84;
  std::uint32_t time_boot_ms = 0;
  float x = 0, y = 0, z = 0, vx = 0, vy = 0, vz = 0, afx = 0, afy = 0, afz = 0, yaw = 0,
        yaw_rate = 0;
  std::uint16_t type_mask = 0;
  std::uint8_t target_system = 0, target_component = 0, coordinate_frame = 0;
  template <class V>
  void Visit(V& v) {
    v(time_boot_ms), v(x), v(y), v(z), v(vx), v(vy), v(vz), v(afx), v(afy), v(afz), v(yaw),
        v(yaw_rate), v(type_mask), v(target_system), v(target_component), v(coordinate_frame);
  }
};

struct PositionTargetLocalNed {
  static constexpr std::uint32_t kId = 85;
  std::uint32_t time_boot_ms = 0;
  float x = 0, y = 0, z = 0, vx = 0, vy = 0, vz = 0, afx = 0, afy = 0, afz = 0, yaw = 0,
        yaw_rate = 0;
  std::uint16_t type_mask = 0;
  std::uint8_t coordinate_frame = 0;
  template <class V>
  void Visit(V& v) {
    v(time_boot_ms), v(x), v(y), v(z), v(vx), v(vy), v(vz), v(afx), v(afy), v(afz), v(yaw),
        v(yaw_rate), v(type_mask), v(coordinate_frame);
  }
};

struct ExtendedSysState {
  static constexpr std::uint32_t kId = 245;
  std::uint8_t vtol_state = 0, landed_state = 0;
  template <class V>
  void Visit(V& v) {
    v(vtol_state), v(landed_state);
  }
};

struct StatusText {
  static constexpr std::uint32_t kId = 253;
  std::uint8_t severity = 6;    // MAV_SEVERITY_INFO
  std::array<char, 50> text{};  // not NUL-terminated when full
  std::uint16_t id = 0;         // extension
  std::uint8_t chunk_seq = 0;   // extension
  template <class V>
  void Visit(V& v) {
    v(severity), v(text), v(id), v(chunk_seq);
  }
  void SetText(const std::string& s);
  std::string Text() const;
};

/// Little-endian field writer / reader used by Visit().
class PayloadWriter {
 public:
  template <class T>
  PayloadWriter& operator()(const T& value) {
    const std::size_t at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &value, sizeof(T));  // x86-64 and ARM64 are little-endian
    return *this;
  }
  template <std::size_t N>
  PayloadWriter& operator()(const std::array<char, N>& text) {
    bytes.insert(bytes.end(), text.begin(), text.end());
    return *this;
  }
  std::vector<std::uint8_t> bytes;
};

class PayloadReader {
 public:
  /// Reads `payload`, zero-extended to `full_length`.
  PayloadReader(const std::vector<std::uint8_t>& payload, std::size_t full_length)
      : bytes_(payload) {
    if (bytes_.size() < full_length) bytes_.resize(full_length, 0);
  }
  template <class T>
  PayloadReader& operator()(T& value) {
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return *this;
  }
  template <std::size_t N>
  PayloadReader& operator()(std::array<char, N>& text) {
    std::memcpy(text.data(), bytes_.data() + at_, N);
    at_ += N;
    return *this;
  }

 private:
  std::vector<std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

static_assert(sizeof(float) == 4, "MAVLink floats are IEEE 754 single precision");

template <class M>
std::vector<std::uint8_t> Pack(const M& message) {
  PayloadWriter writer;
  M copy = message;  // Visit is shared by both directions, so it takes a mutable object
  copy.Visit(writer);
  return writer.bytes;
}

/// Precondition: frame.msgid == M::kId (the frame's payload is at most 255 bytes;
/// longer payloads than the message are ignored past its length).
template <class M>
M Unpack(const Frame& frame) {
  M message;
  PayloadReader reader(frame.payload, FindMessage(M::kId)->length);
  message.Visit(reader);
  return message;
}

}  // namespace mavlink
}  // namespace aerograsp
