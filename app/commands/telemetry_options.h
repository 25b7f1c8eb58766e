// The telemetry options shared by `mission`, `bench`, `replay` and
// `calibrate` (--telemetry YAML, --no-mcap) and the sinks they open.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "telemetry/telemetry.h"
#include "telemetry/telemetry_config.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct TelemetryOptions {
  std::string config_path;  ///< telemetry YAML; empty: data/config/telemetry.yaml
  bool no_mcap = false;     ///< no MCAP file, whatever the config says
  bool ros2 = false;        ///< publish ROS 2 topics (docs/ros2.md), whatever the config says
  int ros2_domain = -1;     ///< ROS_DOMAIN_ID [0, 232] (implies ros2); < 0: the config's
};

/// Adds --telemetry, --no-mcap, --ros2 and --ros2-domain to `cmd` (a CLI11 subcommand).
void AddTelemetryOptions(CLI::App* cmd, TelemetryOptions* options);

/// Reads the telemetry config of `options` (data/config/telemetry.yaml unless
/// one is given) with the command line's overrides applied.
/// @throws ConfigError naming the file, the key and the bound.
TelemetryConfig LoadTelemetryConfig(const TelemetryOptions& options);

class McapSink;

/// The sinks a command hands its telemetry to.
struct CommandTelemetry {
  std::unique_ptr<FanOutSink> sinks = std::make_unique<FanOutSink>();
  const McapSink* mcap = nullptr;  ///< owned by `sinks`; null when off or not created
  /// /NS/emergency_stop heard over ROS 2 (ros2/ros2_bridge.h) for the command
  /// to poll; null when ROS 2 is off or could not start.
  std::unique_ptr<EmergencyStopSource> emergency_stop;

  /// What the command passes on: null when there is no sink.
  TelemetrySink* sink() const { return sinks->empty() ? nullptr : sinks.get(); }
  /// Closes every sink; one line saying what was written ("" when nothing).
  std::string Close();
};

/// The sinks of a command writing its results to `out_dir`: the MCAP file
/// `out_dir/<name>.mcap` unless turned off, and the ROS 2 topics when on. A sink that cannot start
/// (an unwritable folder) or fails later (a full disk) tells `note` once and the command goes on
/// without it; `note` must outlive the sinks.
CommandTelemetry OpenTelemetry(const TelemetryConfig& config, const std::string& out_dir,
                               const std::string& name,
                               const std::function<void(const std::string&)>& note);

}  // namespace aerograsp
