// `aerograsp robot CONFIG`: what the platform is made of, for a user checking a
// configuration before flying it.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct RobotCommandOptions {
  std::string config_path;    ///< platform YAML
  int reach_samples = 20000;  ///< random configurations for the workspace figures
  std::uint32_t seed = 1;     ///< seed of those samples
  std::string plot_path;      ///< when set, a PNG of the platform with the arms at home
};

/// Loads the platform and prints its transform tree, camera, safe volume, and
/// for each arm its chain, limits, reach and home pose.
/// @throws ConfigError / UrdfError with the file and what is wrong.
void RunRobotCommand(const RobotCommandOptions& options, std::ostream& out);

/// Adds `robot`'s options to `cmd` (a CLI11 subcommand); the platform YAML
/// defaults to data/config/platform_4dof.yaml.
void AddRobotOptions(CLI::App* cmd, RobotCommandOptions* options);

}  // namespace aerograsp
