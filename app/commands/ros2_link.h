// ROS 2 for the commands that have telemetry (mission, bench, replay,
// calibrate): the `ros2:` section of the telemetry file with the command
// line's --ros2 and --ros2-domain applied, and the bridge (ros2/ros2_bridge.h)
// opened on it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "app/commands/telemetry_options.h"
#include "ros2/ros2_config.h"
#include "telemetry/telemetry.h"

namespace aerograsp {

/// The ROS 2 settings of `options`: the telemetry file's `ros2:` section
/// (data/config/telemetry.yaml unless --telemetry names one), turned on by
/// --ros2 or --ros2-domain, whose id replaces the file's.
/// @throws ConfigError naming the file, the key and the bound.
Ros2Config LoadRos2Config(const TelemetryOptions& options);

/// When ROS 2 is on: joins the domain, adds the publishing sink to `sinks` and
/// returns the emergency-stop source for the mission to poll. Off, or when DDS
/// cannot start (said once through `note`): adds nothing and returns null.
std::unique_ptr<EmergencyStopSource> OpenRos2Link(const Ros2Config& config, FanOutSink* sinks,
                                                  std::function<void(const std::string&)> note);

}  // namespace aerograsp
