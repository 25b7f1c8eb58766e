// `aerograsp mission`: flies one simulated mission (or N seeded ones) and
// writes DIR/index.html (plots of the estimated object pose against truth,
// joints' targets against actual values with grasp switches, the state
// timeline and a camera frame with the detection), DIR/summary.json and
// DIR/mission.log (every transition with its cause) and the telemetry
// (app/commands/telemetry_options.h: DIR/mission.mcap) of the first run.
#pragma once

#include <ostream>
#include <string>

#include "app/commands/telemetry_options.h"
#include "app/runtime/mission_runner.h"

namespace CLI {
class App;
}

namespace aerograsp {

struct MissionCommandOptions {
  MissionOptions mission;
  std::string out_dir;         ///< report folder (written aside, renamed at the end)
  int runs{1};                 ///< seeded missions: seeds seed, seed + 1, ...
  bool overwrite{false};       ///< replace a report already in out_dir (app/report/report_folder.h)
  TelemetryOptions telemetry;  ///< of the first run only when there are several
};

/// Adds the mission options to `cmd` (a CLI11 subcommand).
void AddMissionOptions(CLI::App* cmd, MissionCommandOptions* options);

/// Runs the mission(s), prints transitions (one run) or a progress bar (several)
/// to `out`/`err`, and writes the report. A failed mission is a result, not an
/// error: it is reported in summary.json and on `out`, and the result is
/// kExitMissionFailed (app/exit_codes.h) when any mission failed, else kExitOk.
/// @throws ConfigError / MeshError / HardwareError for bad inputs,
/// std::runtime_error when the report cannot be written.
int RunMissionCommand(const MissionCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace aerograsp
