#include "app/benchmarks/render_benchmark.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/cli_checks.h"
#include "app/report/report_folder.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "core/data_dir.h"
#include "core/thread_clock.h"
#include "hardware/sim/d435_model.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {}  // namespace

void RunRenderBenchmark(const RenderBenchmarkOptions& options, std::ostream& out) {
  std::optional<ReportFolder> folder;
  if (!options.out_dir.empty()) folder.emplace(options.out_dir, options.overwrite);
  const std::string world_path =
      options.world_config.empty() ? DataPath("config/world_default.yaml") : options.world_config;
  WorldConfig config = WorldConfig::Load(world_path);
  config.object.motion = "crawl";
  World world(config, options.seed);
  // SimCamera's scene without the arms (out of view while hovering), timed stage by stage.
  RgbdRenderer renderer;
  for (const RenderMesh& mesh : world.static_scene())
    renderer.AddMesh(mesh, RgbdRenderer::Motion::kStatic);
  const int object_id = renderer.AddMesh(world.object_render_mesh());
  const CameraIntrinsics& K = world.platform().camera();
  FastRandom rng(options.seed);
  RenderBuffers truth;
  RgbdFrame frame;
  std::vector<double> raycast_ms, model_ms, total_ms, wall_ms;
  for (int i = 0; i < options.frames; ++i) {
    world.StepTo(i / config.camera.frame_rate_hz);
    const auto wall0 = std::chrono::steady_clock::now();
    const double t0 = ThreadCpuMs();
    renderer.SetPose(object_id, world.wMo());
    renderer.Render(world.wMc(), K, Lighting{}, &truth);
    const double t1 = ThreadCpuMs();
    SimulateD435(config.camera.d435, K, truth, &rng, &frame);
    const double t2 = ThreadCpuMs();
    wall_ms.push_back(
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    raycast_ms.push_back(t1 - t0);
    model_ms.push_back(t2 - t1);
    total_ms.push_back(t2 - t0);
  }
  const double budget_ms = 20.0;
  out << fmt::format(
      "render benchmark: {} frames {}x{}, world {}, seed {} (CPU time of one thread)\n",
      options.frames, K.width, K.height, world_path, options.seed);
  out << fmt::format("  {:<22} {:>9} {:>9}\n", "stage", "median", "p90");
  out << fmt::format("  {:<22} {:>6.2f} ms {:>6.2f} ms\n", "ray casting + shading",
                     Percentile(raycast_ms, 0.5), Percentile(raycast_ms, 0.9));
  out << fmt::format("  {:<22} {:>6.2f} ms {:>6.2f} ms\n", "D435 model", Percentile(model_ms, 0.5),
                     Percentile(model_ms, 0.9));
  out << fmt::format("  {:<22} {:>6.2f} ms {:>6.2f} ms   (budget {:.0f} ms)\n",
                     "colour + depth frame", Percentile(total_ms, 0.5), Percentile(total_ms, 0.9),
                     budget_ms);
  out << fmt::format("  {:<22} {:>6.2f} ms {:>6.2f} ms\n", "wall time", Percentile(wall_ms, 0.5),
                     Percentile(wall_ms, 0.9));
  if (!options.out_dir.empty()) {
    nlohmann::json summary = {
        {"stage", "render"},
        {"frames", options.frames},
        {"width", K.width},
        {"height", K.height},
        {"seed", options.seed},
        {"raycast_ms_median", Percentile(raycast_ms, 0.5)},
        {"d435_model_ms_median", Percentile(model_ms, 0.5)},
        {"frame_ms_median", Percentile(total_ms, 0.5)},
        {"frame_ms_p90", Percentile(total_ms, 0.9)},
        {"wall_ms_median", Percentile(wall_ms, 0.5)},
        {"budget_ms", budget_ms},
    };
    const std::string path = WriteSummaryFile(folder->path(), summary.dump(2));
    folder->Commit();
    out << "  summary: " << folder->Final(path) << "\n";
  }
}

void AddRenderBenchmarkOptions(CLI::App* cmd, RenderBenchmarkOptions* o) {
  cmd->add_option("--out", o->out_dir, "Folder for summary.json");
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--frames", o->frames, "Frames to render")
      ->capture_default_str()
      ->check(cli::Range(1, 100000));
  cmd->add_option("--seed", o->seed, "World seed")->capture_default_str()->check(cli::Seed());
  cmd->add_option("--world", o->world_config, "World YAML")->check(CLI::ExistingFile);
}

}  // namespace aerograsp
