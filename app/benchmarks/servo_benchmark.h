// `aerograsp benchmark servo`: convergence, iterations, step time and
// safe-volume entries of the dual-arm servo on random reachable targets, the
// same targets solved by orocos KDL's joint-limited Newton-Raphson IK, and a
// long run of random trials that counts safe-volume entries.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace aerograsp {

struct ServoBenchmarkOptions {
  std::string out_dir;               ///< summary.json goes here (written aside, renamed)
  bool overwrite = false;            ///< replace a report already in out_dir
  std::vector<std::string> configs;  ///< platform YAMLs; empty: the 4-DoF and 6-DoF ones
  int trials{1000};                  ///< dual-arm trials per config: 2 targets each
  int safety_trials{10000};          ///< random trials counting safe-volume entries; 0 skips
  std::uint32_t seed{1};             ///< of targets and starts
  double dt_s{0.01};                 ///< servo period, s
  double trial_timeout_s{8.0};       ///< per convergence trial, s
  double safety_trial_s{3.0};        ///< per safety trial, s (a target switch at half time)
  double margin_m{0.005};  ///< clearance the servo keeps from the safe volume and the other arm, m
};

/// Adds `benchmark servo` options to `servo_cmd` (a CLI11 subcommand).
void AddServoBenchmarkOptions(CLI::App* servo_cmd, ServoBenchmarkOptions* options);

/// Runs the benchmark, prints the figures with progress lines to `out` and
/// writes out_dir/summary.json.
/// @throws ConfigError / UrdfError for a bad config, std::runtime_error when the
/// summary cannot be written.
void RunServoBenchmark(const ServoBenchmarkOptions& options, std::ostream& out);

}  // namespace aerograsp
