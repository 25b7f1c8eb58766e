#include "app/commands/telemetry_options.h"

#include <CLI/CLI.hpp>

#include "core/data_dir.h"

namespace aerograsp {

void AddTelemetryOptions(CLI::App* cmd, TelemetryOptions* o) {
  cmd->add_option("--telemetry", o->config_path,
                  "Telemetry YAML: the MCAP log's images and rates [data/config/telemetry.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-mcap", o->no_mcap, "Write no MCAP log (Foxglove, ROS 2 tools)");
}

TelemetryConfig LoadTelemetryConfig(const TelemetryOptions& options) {
  TelemetryConfig config = TelemetryConfig::Load(
      options.config_path.empty() ? DataPath("config/telemetry.yaml") : options.config_path);
  if (options.no_mcap) config.mcap.enabled = false;
  return config;
}

std::unique_ptr<FanOutSink> OpenTelemetry(const TelemetryConfig& /*config*/,
                                          const std::string& /*out_dir*/,
                                          const std::string& /*name*/,
                                          std::function<void(const std::string&)> /*note*/) {
  return std::make_unique<FanOutSink>();
}

}  // namespace aerograsp
