#include "telemetry/telemetry_config.h"

#include "core/config.h"

namespace aerograsp {

TelemetryConfig TelemetryConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"mcap", "ros2"});  // ros2: ros2/ros2_config.h reads it
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
  c.Validate();
  return c;
}

void TelemetryConfig::Validate() const {
  const std::string& s = source;
  CheckRange(s, "mcap.image_rate_hz", mcap.image_rate_hz, 1e-3, 60.0, "Hz");
  CheckRange(s, "mcap.jpeg_quality", mcap.jpeg_quality, 10, 100, "");
  CheckRange(s, "mcap.state_rate_hz", mcap.state_rate_hz, 1e-3, 1000.0, "Hz");
  CheckOneOf(s, "mcap.compression", mcap.compression, {"none", "lz4", "zstd"});
  CheckRange(s, "mcap.chunk_size_kib", mcap.chunk_size_kib, 16, 65536, "KiB");
}

}  // namespace aerograsp
