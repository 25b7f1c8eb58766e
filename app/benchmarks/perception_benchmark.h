// `aerograsp benchmark perception`: the tracker on plain meshes against the
// same objects with their colours. For each object and motion it records a
// simulated sequence (`aerograsp record`), writes the object's mesh with its
// vertex colours stripped, and replays the sequence (`aerograsp replay`, the
// code's default perception settings) with the coloured and with the plain
// mesh, with the detector and without it (the first pose from the truth; the
// global registration on the whole frame after a loss), ViSP's
// vpMbGenericTracker beside ours. Prints a table and writes
// DIR/summary.json; the sequences and every replay's outputs stay in DIR.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace aerograsp {

struct PerceptionBenchmarkOptions {
  std::string out_dir;     ///< required; written aside, renamed at the end
  bool overwrite = false;  ///< replace a report already in out_dir
  std::vector<std::string> objects{"crawler", "pipe", "u_shape"};  ///< shipped names or paths
  std::vector<std::string> motions{"static", "crawl"};             ///< `record --motion`
  int frames = 150;        ///< frames per sequence, [10, 100000]
  std::uint64_t seed = 1;  ///< world seed of every recording
  bool run_peer = true;    ///< ViSP's tracker beside ours
  /// Perception YAML for every replay; "" = the code's defaults.
  std::string perception_config;
};

/// Throws ConfigError / MeshError / HardwareError naming the file on bad input
/// (an unknown object, an unwritable folder).
void RunPerceptionBenchmark(const PerceptionBenchmarkOptions& options, std::ostream& out,
                            std::ostream& progress);

/// Adds `benchmark perception`'s options to `cmd` (a CLI11 subcommand).
void AddPerceptionBenchmarkOptions(CLI::App* cmd, PerceptionBenchmarkOptions* options);

}  // namespace aerograsp
