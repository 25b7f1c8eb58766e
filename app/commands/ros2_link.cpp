#include "app/commands/ros2_link.h"

#include "core/data_dir.h"
#include "ros2/ros2_bridge.h"

namespace aerograsp {

Ros2Config LoadRos2Config(const TelemetryOptions& options) {
  Ros2Config config = Ros2Config::Load(
      options.config_path.empty() ? DataPath("config/telemetry.yaml") : options.config_path);
  if (options.ros2 || options.ros2_domain >= 0) config.enabled = true;
  if (options.ros2_domain >= 0) config.domain_id = options.ros2_domain;
  return config;
}

std::unique_ptr<EmergencyStopSource> OpenRos2Link(const Ros2Config& config, FanOutSink* sinks,
                                                  std::function<void(const std::string&)> note) {
  Ros2Bridge bridge = OpenRos2(config, std::move(note));
  if (!bridge) return nullptr;
  sinks->Add(std::move(bridge.sink));
  return std::move(bridge.emergency_stop);
}

}  // namespace aerograsp
