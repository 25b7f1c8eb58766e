// `aerograsp benchmark render`: speed of the simulated D435 (ray casting and
// sensor model) on the default world, printed and written to summary.json.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct RenderBenchmarkOptions {
  std::string out_dir;     ///< summary.json goes here (written aside, renamed); empty: print only
  bool overwrite = false;  ///< replace a report already in out_dir
  int frames = 100;        ///< frames rendered, [1, 100000]
  std::uint64_t seed = 1;
  std::string world_config;  ///< default data/config/world_default.yaml
};

/// Renders `frames` frames of a hovering vehicle with a crawling object and
/// reports per-frame time of the ray casting, of the D435 model and of both
/// (median and 90th percentile, CPU time of this thread, and wall time).
void RunRenderBenchmark(const RenderBenchmarkOptions& options, std::ostream& out);

/// Adds `benchmark render`'s options to `cmd` (a CLI11 subcommand).
void AddRenderBenchmarkOptions(CLI::App* cmd, RenderBenchmarkOptions* options);

}  // namespace aerograsp
