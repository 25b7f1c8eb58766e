// `aerograsp record`: a simulated RGB-D sequence with ground truth, in the
// format ReplayCamera reads (hardware/sequence.h).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct RecordCommandOptions {
  std::string out_dir;       ///< the sequence folder to create
  int frames = 300;          ///< number of frames, [1, 1e6]
  std::uint64_t seed = 1;    ///< world seed: the same seed gives the same sequence
  std::string world_config;  ///< world YAML (data/config/world_default.yaml by default)
  std::string object;        ///< overrides the world's object when not empty
  std::string motion;        ///< overrides the world's object motion when not empty
  bool overwrite = false;    ///< replace a sequence already in out_dir
  /// >= 0: a panel hides the object from this time on (WorldConfig::occluder)
  double occlude_at_s = -1.0;
  double occlude_for_s = 1.0;    ///< how long it hides it, s
  double occlude_every_s = 0.0;  ///< hides it again every this many seconds (0: once)
};

/// Runs the simulator at the camera's frame rate and writes every frame, the
/// ground truth cMo, the vehicle state and the joints, plus preview_color.png
/// and preview_depth.png (frame 0, depth coloured by range). Prints a summary
/// to `out` and progress to `progress`.
/// @throws ConfigError / HardwareError / MeshError naming the file and what is wrong.
void RunRecordCommand(const RecordCommandOptions& options, std::ostream& out,
                      std::ostream& progress);

/// Adds `record`'s options to `cmd` (a CLI11 subcommand).
void AddRecordOptions(CLI::App* cmd, RecordCommandOptions* options);

}  // namespace aerograsp
