// `aerograsp benchmark missions`: the simulated mission flown over every
// combination of arms (4dof, 6dof), object (crawler, pipe, u_shape) and
// object motion (crawl, static): the default one (4dof-crawler-crawl, the
// `mission` command's defaults) on `runs_default` seeds, each other one on
// `runs` seeds, all from the same first seed. It prints a progress line per
// mission, a line per configuration and a table with one row per
// configuration (app/report/mission_statistics.h: first-attempt and within-3
// success, time to grasp, closes and holds, tool error at contact, estimate
// RMSE while grasping, safety counts, worst servo step, real-time factor).
// DIR/summary.json holds every configuration's figures, DIR/index.html their
// table, and DIR/<configuration>/ the report of its missions as
// `mission --runs` writes it (app/commands/mission_runs.h). docs/benchmarks.md
// has the method.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace aerograsp {

/// One combination flown by the benchmark.
struct MissionBenchmarkConfig {
  std::string arm;     ///< "4dof" | "6dof"
  std::string object;  ///< "crawler" | "pipe" | "u_shape"
  std::string motion;  ///< "crawl" | "static"
  /// "ARM-OBJECT-MOTION", e.g. "6dof-pipe-static".
  std::string name() const { return arm + "-" + object + "-" + motion; }
};

/// The twelve combinations, the default one (4dof-crawler-crawl) first.
std::vector<MissionBenchmarkConfig> MissionBenchmarkConfigs();

struct MissionBenchmarkOptions {
  std::string out_dir;  ///< report folder
  bool overwrite{false};
  int runs_default{100};  ///< seeds of the default combination, [1, 100000]
  int runs{30};           ///< seeds of each other combination, [1, 100000]
  std::uint64_t seed{1};  ///< first seed of every combination
  /// Combinations flown, by name (MissionBenchmarkConfig::name); empty: all.
  std::vector<std::string> configs;
  std::string config_path;  ///< mission YAML; empty: data/config/mission_default.yaml
  double timeout_s{-1.0};   ///< mission time limit, s; < 0: the mission config's
};

/// Adds the options to `cmd` (a CLI11 subcommand).
void AddMissionBenchmarkOptions(CLI::App* cmd, MissionBenchmarkOptions* options);

/// Flies the missions (progress on `err`), prints the table on `out`, writes
/// the report. Returns kExitOk when every mission succeeded, else
/// kExitMissionFailed (app/exit_codes.h).
/// @throws ConfigError for an unknown configuration name or a bad mission
/// config, std::runtime_error when the report cannot be written.
int RunMissionBenchmark(const MissionBenchmarkOptions& options, std::ostream& out,
                        std::ostream& err);

}  // namespace aerograsp
