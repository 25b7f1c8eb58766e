// `aerograsp benchmark faults`: seeded missions, each with one fault injected
// at a random time of the simulated clock, flown over the real drivers and the
// simulated peers (data/config/hardware_sim.yaml: the SCS driver on the
// simulated bus, the PX4 client on the simulated PX4) and the simulated camera.
// Per fault kind it reports how often the arms reached the safe state, how
// long after the fault first showed on a device (its detectability), any
// safe-volume entry or arm contact, and whether each mission's log is complete
// (the fault named once, the mission's end); DIR/summary.json holds every
// mission, DIR/logs/ every mission.log. docs/reliability.md has the method.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace aerograsp {

struct FaultBenchmarkOptions {
  std::string out_dir;  ///< report folder
  bool overwrite{false};
  int missions{100};  ///< [1, 10000]; the kinds take turns
  std::uint64_t seed{1};
  /// data/config/hardware_sim.yaml when empty.
  std::string hardware_path;
  /// Fault kinds flown (servo_silent, servo_slow, bus_corrupt, link_loss,
  /// command_rejected, camera_frozen, camera_no_depth, object_knocked_off);
  /// empty: all.
  std::vector<std::string> kinds;
  double from_s{4.0};  ///< faults injected uniformly in [from_s, to_s] of the simulated clock
  double to_s{20.0};
};

/// Adds the options to `cmd` (a CLI11 subcommand).
void AddFaultBenchmarkOptions(CLI::App* cmd, FaultBenchmarkOptions* options);

/// Flies the missions, prints a progress line each and the table, writes
/// DIR/summary.json and DIR/logs/. @throws ConfigError / HardwareError for bad
/// inputs, std::runtime_error when the report cannot be written.
void RunFaultBenchmark(const FaultBenchmarkOptions& options, std::ostream& out);

}  // namespace aerograsp
