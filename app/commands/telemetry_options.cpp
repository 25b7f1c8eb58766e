#include "app/commands/telemetry_options.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "core/data_dir.h"
#include "ros2/ros2_bridge.h"
#include "telemetry/mcap_sink.h"

namespace aerograsp {

void AddTelemetryOptions(CLI::App* cmd, TelemetryOptions* o) {
  cmd->add_option("--telemetry", o->config_path,
                  "Telemetry YAML: the MCAP log's images and rates [data/config/telemetry.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-mcap", o->no_mcap, "Write no MCAP log (Foxglove, ROS 2 tools)");
  cmd->add_flag("--ros2", o->ros2,
                "Publish ROS 2 topics over DDS and hear /aerograsp/emergency_stop (docs/ros2.md)");
  cmd->add_option("--ros2-domain", o->ros2_domain, "ROS_DOMAIN_ID for --ros2 (implies it) [0]")
      ->check(CLI::Range(0, 232));
}

TelemetryConfig LoadTelemetryConfig(const TelemetryOptions& options) {
  TelemetryConfig config = TelemetryConfig::Load(
      options.config_path.empty() ? DataPath("config/telemetry.yaml") : options.config_path);
  if (options.no_mcap) config.mcap.enabled = false;
  if (options.ros2 || options.ros2_domain >= 0) config.ros2.enabled = true;
  if (options.ros2_domain >= 0) config.ros2.domain_id = options.ros2_domain;
  return config;
}

CommandTelemetry OpenTelemetry(const TelemetryConfig& config, const std::string& out_dir,
                               const std::string& name,
                               const std::function<void(const std::string&)>& note) {
  CommandTelemetry t;
  if (config.mcap.enabled) {
    const std::string path = (std::filesystem::path(out_dir) / (name + ".mcap")).string();
    try {
      auto mcap = std::make_unique<McapSink>(path, config.mcap, note);
      t.mcap = mcap.get();
      t.sinks->Add(std::move(mcap));
    } catch (const std::exception& e) {
      if (note) note(std::string("no MCAP log: ") + e.what() + "; the run goes on without it");
    }
  }
  Ros2Bridge ros2 = OpenRos2(config.ros2, note);  // empty when off or when DDS cannot start
  if (ros2) {
    t.sinks->Add(std::move(ros2.sink));
    t.emergency_stop = std::move(ros2.emergency_stop);
  }
  return t;
}

std::string CommandTelemetry::Close() {
  sinks->Close();
  if (!mcap || mcap->writer().failed()) return "";
  return fmt::format("{} ({:.1f} MB, {} messages)", mcap->writer().path(),
                     mcap->writer().bytes_written() / 1e6, mcap->writer().message_count());
}

}  // namespace aerograsp
