#include "app/benchmarks/perception_benchmark.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/cli_checks.h"
#include "app/commands/record_command.h"
#include "app/commands/replay_command.h"
#include "app/report/report_folder.h"
#include "app/report/summary_file.h"
#include "core/config.h"
#include "core/mesh.h"
#include "core/object_model.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

/// How a replay finds the object: the detector on every frame until found, or
/// no detector, the first pose given (the truth) and the global registration
/// on the whole frame after a loss, or no detector and no first pose (the
/// search starts on the whole frame).
struct Mode {
  const char* name;
  bool detector;
  bool init_from_truth;
};
constexpr Mode kModes[] = {
    {"detector", true, false}, {"no-detector", false, true}, {"search", false, false}};

/// One replay's figures, from its summary.json.
struct Figures {
  double recall = NAN, t_rmse_mm = NAN, r_rmse_deg = NAN, frame_ms = NAN, global_ms = NAN;
  int searches = 0, found = 0;
  double peer_recall = NAN, peer_t_rmse_mm = NAN, peer_frame_ms = NAN;
  nlohmann::json summary;
};

double Number(const nlohmann::json& j, const char* key, double scale = 1.0) {
  return j.contains(key) && j[key].is_number() ? scale * j[key].get<double>() : NAN;
}

Figures ReadFigures(const std::string& summary_path) {
  std::ifstream in(summary_path);
  if (!in) throw std::runtime_error(summary_path + ": cannot be read");
  Figures f;
  in >> f.summary;
  const nlohmann::json& s = f.summary;
  f.recall = Number(s, "detection_recall");
  f.t_rmse_mm = Number(s, "translation_rmse_m", 1e3);
  f.r_rmse_deg = Number(s, "rotation_rmse_deg");
  f.frame_ms = Number(s, "frame_ms_median");
  if (s.contains("global_search")) {
    f.global_ms = Number(s["global_search"], "cpu_ms_per_frame_mean");
    f.searches = s["global_search"].value("searches", 0);
    f.found = s["global_search"].value("found", 0);
  }
  if (s.contains("visp_peer")) {
    f.peer_recall = Number(s["visp_peer"], "detection_recall");
    f.peer_t_rmse_mm = Number(s["visp_peer"], "translation_rmse_m", 1e3);
    f.peer_frame_ms = Number(s["visp_peer"], "frame_ms_median");
  }
  return f;
}

std::string Cell(double v, const char* format = "{:.2f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string("-");
}

/// The object's mesh with its vertex colours stripped, written as PLY under dir.
std::string WritePlainMesh(const ObjectModel& object, const fs::path& dir) {
  TriangleMesh plain = object.mesh_o;
  plain.colors.clear();
  fs::create_directories(dir);
  const std::string path = (dir / (object.name + ".ply")).string();
  SaveMeshPly(plain, path);
  return path;
}

}  // namespace

void RunPerceptionBenchmark(const PerceptionBenchmarkOptions& options, std::ostream& out,
                            std::ostream& progress) {
  if (options.out_dir.empty())
    throw std::invalid_argument("benchmark perception: --out is required");
  if (options.frames < 10 || options.frames > 100000)
    throw std::invalid_argument("benchmark perception: --frames must be in [10, 100000]");
  ReportFolder folder(options.out_dir, options.overwrite);
  const fs::path root(folder.path());
  nlohmann::json rows = nlohmann::json::array();
  std::ostringstream table;
  table << fmt::format(
      "{:<9} {:<7} {:<12} | {:>7} {:>7} {:>7} {:>6} {:>7} | {:>7} {:>7} {:>7} "
      "{:>6} {:>7} {:>7} | {:>7} {:>7} {:>6}\n",
      "object", "motion", "mode", "recall", "t mm", "r deg", "ms", "glob ms", "recall", "t mm",
      "r deg", "ms", "glob ms", "search", "recall", "t mm", "ms");
  table << fmt::format("{:<30} | {:<39} | {:<55} | {:<22}\n", "", "coloured mesh",
                       "plain mesh (no vertex colours)", "ViSP mbt, plain mesh");
  int rows_plain_recall_ok = 0, rows_rmse_ok = 0, row_count = 0;
  for (const std::string& name : options.objects) {
    const ObjectModel object = ObjectModel::Load(name);
    const std::string plain_mesh =
        WritePlainMesh(object, root / "objects" / (object.name + "_plain"));
    const std::string detector = ObjectDetectorPath(object);
    if (detector.empty()) {
      throw ConfigError(object.source +
                        ": the object has no detector (train one: "
                        "scripts/train_detectors.sh " +
                        object.reference + ")");
    }
    for (const std::string& motion : options.motions) {
      const std::string tag = object.name + "_" + motion;
      RecordCommandOptions record;
      record.out_dir = (root / "sequences" / tag).string();
      record.frames = options.frames;
      record.seed = options.seed;
      record.object = name;
      record.motion = motion;
      std::ostringstream quiet;
      progress << "benchmark perception: recording " << tag << "\n";
      RunRecordCommand(record, quiet, progress);
      for (const Mode& mode : kModes) {
        Figures figures[2];
        for (int plain = 0; plain < 2; ++plain) {
          ReplayCommandOptions replay;
          replay.sequence = record.out_dir;
          replay.out_dir =
              (root / "replays" / tag / mode.name / (plain ? "plain" : "coloured")).string();
          replay.object = plain ? plain_mesh : name;
          replay.use_detector = mode.detector;
          if (mode.detector) replay.detector = detector;
          replay.init_from_truth = mode.init_from_truth;
          replay.run_peer = options.run_peer && plain;
          replay.perception_config = options.perception_config;
          progress << fmt::format("benchmark perception: replaying {} {} with the {} mesh\n", tag,
                                  mode.name, plain ? "plain" : "coloured");
          RunReplayCommand(replay, quiet, progress);
          figures[plain] = ReadFigures((fs::path(replay.out_dir) / "summary.json").string());
        }
        const Figures& c = figures[0];
        const Figures& p = figures[1];
        const bool recall_ok = p.recall >= 0.98;
        const bool rmse_ok = p.t_rmse_mm <= 1.2 * c.t_rmse_mm;
        ++row_count;
        rows_plain_recall_ok += recall_ok;
        rows_rmse_ok += rmse_ok;
        table << fmt::format(
            "{:<9} {:<7} {:<12} | {:>7} {:>7} {:>7} {:>6} {:>7} | {:>7} {:>7} {:>7} {:>6} {:>7} "
            "{:>7} | {:>7} {:>7} {:>6}\n",
            object.name, motion, mode.name, Cell(100 * c.recall, "{:.1f}"), Cell(c.t_rmse_mm),
            Cell(c.r_rmse_deg), Cell(c.frame_ms, "{:.1f}"), Cell(c.global_ms, "{:.1f}"),
            Cell(100 * p.recall, "{:.1f}"), Cell(p.t_rmse_mm), Cell(p.r_rmse_deg),
            Cell(p.frame_ms, "{:.1f}"), Cell(p.global_ms, "{:.1f}"),
            fmt::format("{}/{}", p.found, p.searches), Cell(100 * p.peer_recall, "{:.1f}"),
            Cell(p.peer_t_rmse_mm), Cell(p.peer_frame_ms, "{:.1f}"));
        auto json_of = [](const Figures& f) {
          nlohmann::json j = {{"recall", f.recall},
                              {"translation_rmse_mm", f.t_rmse_mm},
                              {"rotation_rmse_deg", f.r_rmse_deg},
                              {"frame_ms_median", f.frame_ms},
                              {"global_cpu_ms_per_frame", f.global_ms},
                              {"global_searches", f.searches},
                              {"global_searches_found", f.found}};
          if (std::isfinite(f.peer_recall) || std::isfinite(f.peer_t_rmse_mm))
            j["visp"] = {{"recall", f.peer_recall},
                         {"translation_rmse_mm", f.peer_t_rmse_mm},
                         {"frame_ms_median", f.peer_frame_ms}};
          return j;
        };
        rows.push_back({{"object", object.name},
                        {"motion", motion},
                        {"mode", mode.name},
                        {"frames_visible", p.summary.value("frames_visible", 0)},
                        {"coloured", json_of(c)},
                        {"plain", json_of(p)},
                        {"plain_recall_at_least_98_percent", recall_ok},
                        {"plain_translation_rmse_within_1_2x", rmse_ok}});
      }
    }
  }
  out << fmt::format(
      "perception benchmark: {} frames per sequence, seed {}, perception {} (CPU ms: tracker "
      "thread; glob ms: the global registration's CPU on all cores, per frame on average)\n",
      options.frames, options.seed,
      options.perception_config.empty() ? "code defaults" : options.perception_config);
  out << table.str();
  out << fmt::format(
      "  plain mesh: recall >= 98 % of visible frames in {} of {} rows; translation RMSE within "
      "1.2x of the coloured mesh's in {} of {}\n",
      rows_plain_recall_ok, row_count, rows_rmse_ok, row_count);
  nlohmann::json summary = {
      {"stage", "perception"},
      {"frames", options.frames},
      {"seed", options.seed},
      {"perception",
       options.perception_config.empty() ? "code defaults" : options.perception_config},
      {"rows", rows},
      {"rows_plain_recall_ok", rows_plain_recall_ok},
      {"rows_translation_rmse_ok", rows_rmse_ok},
      {"row_count", row_count}};
  // Figures that could not be measured (nothing found) are NaN: written as null.
  const std::string path = WriteSummaryFile(folder.path(), summary.dump(2));
  folder.Commit();
  out << "  summary: " << folder.Final(path) << "\n";
}

void AddPerceptionBenchmarkOptions(CLI::App* cmd, PerceptionBenchmarkOptions* o) {
  cmd->add_option("--out", o->out_dir, "Folder for everything")->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--objects", o->objects, "Objects")->capture_default_str();
  cmd->add_option("--motions", o->motions, "Object motions")
      ->capture_default_str()
      ->check(CLI::IsMember({"static", "crawl"}));
  cmd->add_option("--frames", o->frames, "Frames per sequence")
      ->capture_default_str()
      ->check(cli::Range(10, 100000));
  cmd->add_option("--seed", o->seed, "World seed")->capture_default_str()->check(cli::Seed());
  cmd->add_flag("!--no-peer", o->run_peer, "Do not run ViSP's tracker beside ours");
  cmd->add_option("--perception", o->perception_config, "Perception YAML [the code's defaults]")
      ->check(CLI::ExistingFile);
}

}  // namespace aerograsp
