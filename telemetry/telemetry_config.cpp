#include "telemetry/telemetry_config.h"

#include <cctype>

#include "core/config.h"

namespace aerograsp {

TelemetryConfig TelemetryConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"mcap", "ros2"});
  TelemetryConfig c;
  c.source = path;
  if (root.Has("mcap")) {
    const ConfigNode m = root.Child("mcap");
    m.RequireOnlyKeys({"enabled", "image_rate_hz", "jpeg_quality", "depth", "state_rate_hz",
                       "compression", "chunk_size_kib"});
    McapConfig& o = c.mcap;
    o.enabled = m.GetBool("enabled", o.enabled);
    o.image_rate_hz = m.GetDouble("image_rate_hz", o.image_rate_hz);
    o.jpeg_quality = m.GetInt("jpeg_quality", o.jpeg_quality);
    o.depth = m.GetBool("depth", o.depth);
    o.state_rate_hz = m.GetDouble("state_rate_hz", o.state_rate_hz);
    o.compression = m.GetString("compression", o.compression);
    o.chunk_size_kib = m.GetInt("chunk_size_kib", o.chunk_size_kib);
  }
  if (root.Has("ros2")) {
    const ConfigNode r = root.Child("ros2");
    r.RequireOnlyKeys({"enabled", "domain_id", "topic_namespace", "dds_config",
                       "joint_states_rate_hz", "image_rate_hz", "publish_clock",
                       "emergency_stop_wait_s"});
    Ros2Config& o = c.ros2;
    o.enabled = r.GetBool("enabled", o.enabled);
    o.domain_id = r.GetInt("domain_id", o.domain_id);
    o.topic_namespace = r.GetString("topic_namespace", o.topic_namespace);
    if (r.Has("dds_config") && !r.GetString("dds_config").empty()) {
      o.dds_config = r.GetPath("dds_config");
      CheckFileExists(path, "ros2.dds_config", o.dds_config);
    }
    o.joint_states_rate_hz = r.GetDouble("joint_states_rate_hz", o.joint_states_rate_hz);
    o.image_rate_hz = r.GetDouble("image_rate_hz", o.image_rate_hz);
    o.publish_clock = r.GetBool("publish_clock", o.publish_clock);
    o.emergency_stop_wait_s = r.GetDouble("emergency_stop_wait_s", o.emergency_stop_wait_s);
  }
  c.Validate(c.source, "");
  return c;
}

void TelemetryConfig::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& s = source;
  CheckRange(s, prefix + "mcap.image_rate_hz", mcap.image_rate_hz, 1e-3, 60.0, "Hz");
  CheckRange(s, prefix + "mcap.jpeg_quality", mcap.jpeg_quality, 10, 100, "");
  CheckRange(s, prefix + "mcap.state_rate_hz", mcap.state_rate_hz, 1e-3, 1000.0, "Hz");
  CheckOneOf(s, prefix + "mcap.compression", mcap.compression, {"none", "lz4", "zstd"});
  CheckRange(s, prefix + "mcap.chunk_size_kib", mcap.chunk_size_kib, 16, 65536, "KiB");
  CheckRange(s, prefix + "ros2.domain_id", ros2.domain_id, 0, 232, "");
  const std::string& ns = ros2.topic_namespace;
  for (const char ch : ns) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '/') {
      throw ConfigError(s + ": " + prefix + "ros2.topic_namespace: '" + ns +
                        "' has a character that is not a letter, digit, '_' or '/'");
    }
  }
  if (!ns.empty() && (ns.front() == '/' || ns.back() == '/' ||
                      std::isdigit(static_cast<unsigned char>(ns.front())) ||
                      ns.find("//") != std::string::npos)) {
    throw ConfigError(s + ": " + prefix + "ros2.topic_namespace: '" + ns +
                      "' must not start with '/' or a digit, end with '/' or hold '//'");
  }
  CheckRange(s, prefix + "ros2.joint_states_rate_hz", ros2.joint_states_rate_hz, 1e-3, 1000.0,
             "Hz");
  CheckRange(s, prefix + "ros2.image_rate_hz", ros2.image_rate_hz, 0.0, 60.0, "Hz");
  CheckRange(s, prefix + "ros2.emergency_stop_wait_s", ros2.emergency_stop_wait_s, 0.0, 600.0, "s");
}

}  // namespace aerograsp
