// Settings of the telemetry a command writes or publishes
// (data/config/telemetry.yaml; each field's unit and range there and here).
#pragma once

#include <string>

namespace aerograsp {

/// The MCAP log written beside a command's report (telemetry/mcap_sink.h).
struct McapConfig {
  bool enabled = true;  ///< write DIR/<command>.mcap
  /// Camera frames kept per second of mission time, (0, 60]; the others are
  /// skipped (the images are most of the file).
  double image_rate_hz = 5.0;
  int jpeg_quality = 75;  ///< [10, 100], OpenCV's IMWRITE_JPEG_QUALITY
  bool depth = false;     ///< also the depth images (16-bit PNG), about 4x a JPEG each
  /// Arms and moving transforms kept per second of mission time, (0, 1000];
  /// at or above the servo rate every cycle is kept.
  double state_rate_hz = 50.0;
  std::string compression = "zstd";  ///< chunk compression: "none" | "lz4" | "zstd"
  int chunk_size_kib = 1024;         ///< a chunk is closed past this much data, [16, 65536] KiB
};

struct TelemetryConfig {
  std::string source;  ///< the file it was read from (for messages)
  McapConfig mcap;

  /// Reads and validates `path`.
  /// @throws ConfigError naming the file, the key and the bound.
  static TelemetryConfig Load(const std::string& path);
  /// @throws ConfigError naming `source`, the key and the bound.
  void Validate() const;
};

}  // namespace aerograsp
