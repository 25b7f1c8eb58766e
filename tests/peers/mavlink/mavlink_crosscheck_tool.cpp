// aerograsp's side of the MAVLink 2 cross-check with node-mavlink (see
// crosscheck.js and run_crosscheck.sh next to this file).
//   mavlink_crosscheck_tool write FILE  frames our encoder writes, with their field values
//   mavlink_crosscheck_tool read FILE   frames node-mavlink wrote: each must parse and
//                                       give the values it lists
// Field values go in wire order, so the layouts are compared too.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_messages.h"

namespace aerograsp {
namespace mavlink {
namespace {

using nlohmann::json;

/// Calls f(M{}) for the message type of `id`; false when not one of ours.
template <class F>
bool ForMessage(std::uint32_t id, F&& f) {
  switch (id) {
    case Heartbeat::kId:
      f(Heartbeat{});
      return true;
    case SysStatus::kId:
      f(SysStatus{});
      return true;
    case Attitude::kId:
      f(Attitude{});
      return true;
    case LocalPositionNed::kId:
      f(LocalPositionNed{});
      return true;
    case CommandLong::kId:
      f(CommandLong{});
      return true;
    case CommandAck::kId:
      f(CommandAck{});
      return true;
    case SetPositionTargetLocalNed::kId:
      f(SetPositionTargetLocalNed{});
      return true;
    case PositionTargetLocalNed::kId:
      f(PositionTargetLocalNed{});
      return true;
    case ExtendedSysState::kId:
      f(ExtendedSysState{});
      return true;
    case StatusText::kId:
      f(StatusText{});
      return true;
    default:
      return false;
  }
}

/// Sets every field from a seeded generator.
struct Filler {
  std::uint32_t state;
  std::uint32_t Next() { return state = state * 1664525u + 1013904223u; }
  template <class T>
  Filler& operator()(T& v) {
    if constexpr (std::is_floating_point_v<T>) {
      v = static_cast<T>((Next() / 4294967295.0 - 0.5) * 2000.0);
    } else {
      v = static_cast<T>(Next());
    }
    return *this;
  }
  template <std::size_t N>
  Filler& operator()(std::array<char, N>& text) {
    text.fill('\0');
    const std::string s = "aerograsp says " + std::to_string(Next());
    std::copy(s.begin(), s.end(), text.begin());
    return *this;
  }
};

/// Lists the fields' values in wire order.
struct ToJson {
  json values = json::array();
  template <class T>
  ToJson& operator()(const T& v) {
    if constexpr (std::is_floating_point_v<T>) {
      if (std::isnan(v))
        values.push_back("NaN");
      else
        values.push_back(static_cast<double>(v));
    } else {
      values.push_back(static_cast<std::int64_t>(v));
    }
    return *this;
  }
  template <std::size_t N>
  ToJson& operator()(const std::array<char, N>& text) {
    values.push_back(std::string(text.data(), std::find(text.begin(), text.end(), '\0')));
    return *this;
  }
};

/// Compares the fields with listed values, in wire order.
struct Compare {
  const json& values;
  std::size_t at = 0;
  std::vector<std::string> errors;
  template <class T>
  Compare& operator()(const T& v) {
    const std::size_t k = at++;
    if (k >= values.size()) {
      errors.push_back("field " + std::to_string(k) + ": node-mavlink listed fewer fields");
      return *this;
    }
    bool same;
    if constexpr (std::is_floating_point_v<T>) {
      same = values[k].is_string() ? std::isnan(v) : static_cast<T>(values[k].get<double>()) == v;
    } else {
      same = values[k].get<std::int64_t>() == static_cast<std::int64_t>(v);
    }
    if (!same)
      errors.push_back("field " + std::to_string(k) + ": " + std::to_string(v) +
                       " != " + values[k].dump());
    return *this;
  }
  template <std::size_t N>
  Compare& operator()(const std::array<char, N>& text) {
    const std::size_t k = at++;
    const std::string ours(text.data(), std::find(text.begin(), text.end(), '\0'));
    if (k >= values.size() || values[k].get<std::string>() != ours) {
      errors.push_back("field " + std::to_string(k) + ": text '" + ours + "'");
    }
    return *this;
  }
};

std::string Hex(const std::vector<std::uint8_t>& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (std::uint8_t b : bytes) {
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

std::vector<std::uint8_t> FromHex(const std::string& hex) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  }
  return out;
}

int Write(const std::string& path) {
  const std::string key_hex = "f0e1d2c3b4a5968778695a4b3c2d1e0f00112233445566778899aabbccddeeff";
  Encoder plain(1, 1);
  Encoder signer(1, 1);
  signer.SetSigning(SigningKey{*ParseKeyHex(key_hex), 5});
  json frames = json::array();
  std::uint64_t timestamp = 34715520000000ull;
  auto emit = [&](std::uint32_t id, auto message, bool is_signed) {
    ToJson values;
    message.Visit(values);
    Encoder& encoder = is_signed ? signer : plain;
    json frame = {{"name", FindMessage(id)->name},
                  {"msgid", id},
                  {"sysid", 1},
                  {"compid", 1},
                  {"seq", encoder.next_seq()},
                  {"signed", is_signed},
                  {"values", values.values}};
    const auto bytes = encoder.Encode(id, Pack(message), ++timestamp);
    if (is_signed) {
      frame["key"] = key_hex;
      frame["link_id"] = 5;
      frame["timestamp"] = timestamp;
    }
    frame["hex"] = Hex(bytes);
    frames.push_back(frame);
  };
  std::uint32_t seed = 1;
  for (std::uint32_t id : {0u, 1u, 30u, 32u, 76u, 77u, 84u, 85u, 245u, 253u}) {
    for (bool is_signed : {false, true}) {
      ForMessage(id, [&](auto message) {
        Filler filler{++seed};
        message.Visit(filler);
        emit(id, message, is_signed);
      });
    }
  }
  // Edge cases: a NaN parameter (PX4's "keep the present value") and an ACK whose
  // extensions are all zero (the payload is cut to the command).
  CommandLong takeoff;
  takeoff.command = kCmdNavTakeoff, takeoff.param4 = std::nanf(""), takeoff.param7 = 502.5f;
  takeoff.target_system = 1, takeoff.target_component = 1;
  emit(CommandLong::kId, takeoff, false);
  CommandAck ack;
  ack.command = kCmdComponentArmDisarm;
  emit(CommandAck::kId, ack, false);
  std::ofstream(path) << frames.dump(1) << "\n";
  std::cout << "aerograsp wrote " << frames.size() << " frames to " << path << "\n";
  return 0;
}

int Read(const std::string& path) {
  std::ifstream file(path);
  const json frames = json::parse(file);
  int failures = 0, signed_count = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const json& f = frames[i];
    const std::string where =
        "frame " + std::to_string(i) + " (" + f["name"].get<std::string>() + ")";
    Parser parser;
    if (f["signed"].get<bool>()) {
      parser.RequireSigning(*ParseKeyHex(f["key"].get<std::string>()));
      ++signed_count;
    }
    int parsed = 0;
    for (std::uint8_t b : FromHex(f["hex"].get<std::string>())) {
      const Parser::Result r = parser.Push(b);
      if (r == Parser::Result::kNeedMore) continue;
      if (r != Parser::Result::kFrame) {
        std::cerr << "  MISMATCH " << where << ": parser result " << static_cast<int>(r) << "\n";
        ++failures;
        continue;
      }
      ++parsed;
      const Frame& frame = parser.frame();
      if (frame.msgid != f["msgid"].get<std::uint32_t>() || frame.sysid != f["sysid"].get<int>() ||
          frame.compid != f["compid"].get<int>() || frame.seq != f["seq"].get<int>()) {
        std::cerr << "  MISMATCH " << where << ": header\n";
        ++failures;
      }
      if (frame.is_signed && (frame.link_id != f["link_id"].get<int>() ||
                              frame.timestamp != f["timestamp"].get<std::uint64_t>())) {
        std::cerr << "  MISMATCH " << where << ": signature link id / timestamp\n";
        ++failures;
      }
      ForMessage(frame.msgid, [&](auto message) {
        message = Unpack<decltype(message)>(frame);
        Compare compare{f["values"], 0, {}};
        message.Visit(compare);
        if (compare.at != f["values"].size()) compare.errors.push_back("field count differs");
        for (const std::string& e : compare.errors)
          std::cerr << "  MISMATCH " << where << ": " << e << "\n";
        failures += static_cast<int>(compare.errors.size());
      });
    }
    if (parsed != 1) {
      std::cerr << "  MISMATCH " << where << ": " << parsed << " frames parsed\n";
      ++failures;
    }
  }
  std::cout << "aerograsp decoded " << frames.size() << " node-mavlink frames (" << signed_count
            << " signed), " << failures << " mismatches\n";
  return failures == 0 ? 0 : 1;
}

}  // namespace
}  // namespace mavlink
}  // namespace aerograsp

int main(int argc, char** argv) {
  const std::string command = argc == 3 ? argv[1] : "";
  if (command == "write") return aerograsp::mavlink::Write(argv[2]);
  if (command == "read") return aerograsp::mavlink::Read(argv[2]);
  std::cerr << "usage: mavlink_crosscheck_tool write|read FILE\n";
  return 2;
}
