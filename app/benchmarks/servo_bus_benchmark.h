// `aerograsp benchmark servo-bus`: the closed-loop cycle of the arm driver
// (one SYNC_WRITE to all 10 servos, a READ of every present position, one
// servo's status) against the simulated SCS bus on a pseudo-terminal, with
// the wire's byte time and the servos' return delay simulated.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct ServoBusBenchmarkOptions {
  std::string out_dir;       ///< summary.json goes here (written aside, renamed); empty: print only
  bool overwrite = false;    ///< replace a report already in out_dir
  int cycles = 2000;         ///< bus cycles timed, [10, 1000000]
  std::string world_config;  ///< default data/config/world_default.yaml
};

/// Runs the loop as fast as the bus allows and reports cycle_hz (cycles per
/// second of the wall time spent in the driver's cycle plus the wire's time,
/// which the simulated bus keeps on the simulated clock), the driver's and
/// pty's rate alone, median and p90 cycle time, and what the wire alone
/// would allow.
void RunServoBusBenchmark(const ServoBusBenchmarkOptions& options, std::ostream& out);

/// Adds `benchmark servo-bus`'s options to `cmd` (a CLI11 subcommand).
void AddServoBusBenchmarkOptions(CLI::App* cmd, ServoBusBenchmarkOptions* options);

}  // namespace aerograsp
