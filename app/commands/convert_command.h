// `aerograsp convert RECORDING --out SEQ`: writes a recording (a RealSense .bag,
// a TUM RGB-D folder, or a sequence folder) as our sequence (hardware/sequence.h),
// depth aligned to colour, with the ground truth when the recording has it.
// The sequence is written to a temporary folder beside SEQ and renamed to SEQ
// only when complete: a failed conversion leaves no sequence behind.
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "hardware/bag/recording.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct ConvertCommandOptions {
  std::string input;    ///< .bag file, TUM RGB-D folder or sequence folder
  std::string out_dir;  ///< the sequence folder to create
  std::string object;   ///< object id recorded in sequence.yaml (shipped name or model path)
  RecordingOptions recording;
  int max_frames = 0;      ///< 0 = all
  bool overwrite = false;  ///< replace a sequence already in out_dir
};

/// @throws HardwareError / ConfigError naming the file and what is wrong; the
/// output folder is then left as it was.
void RunConvertCommand(const ConvertCommandOptions& options, std::ostream& out,
                       std::ostream& progress);

/// Adds the options of recordings from other sources (TUM intrinsics, the
/// object in the world, the colour-depth pairing gap) to `cmd`; the returned
/// function completes `options` once the command line has been parsed.
/// @throws std::invalid_argument (when called) for a zero quaternion
std::function<void()> AddRecordingOptions(CLI::App* cmd, RecordingOptions* options);

/// Adds `convert`'s options to `cmd` (a CLI11 subcommand), with the recording
/// options (AddRecordingOptions).
void AddConvertOptions(CLI::App* cmd, ConvertCommandOptions* options);

}  // namespace aerograsp
