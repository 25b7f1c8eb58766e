#include "app/commands/mission_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/cli_checks.h"
#include "app/exit_codes.h"
#include "app/report/mission_report.h"
#include "app/report/progress.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

nlohmann::json RunJson(std::uint64_t seed, const MissionResult& r) {
  nlohmann::json j;
  j["seed"] = seed;
  j["success"] = r.success;
  j["failure"] = r.failure;
  j["time_to_grasp_s"] =
      r.time_to_grasp_s >= 0 ? nlohmann::json(r.time_to_grasp_s) : nlohmann::json(nullptr);
  j["pose_rmse_m"] = r.pose_rmse_m >= 0 ? nlohmann::json(r.pose_rmse_m) : nlohmann::json(nullptr);
  j["rotation_rmse_deg"] =
      r.rotation_rmse_deg >= 0 ? nlohmann::json(r.rotation_rmse_deg) : nlohmann::json(nullptr);
  j["grasp_switches"] = r.grasp_switches;
  j["attempts"] = r.attempts;
  j["safe_volume_entries"] = r.safe_volume_entries;
  j["emergency_stops"] = r.emergency_stops;
  j["realtime_factor"] = r.realtime_factor;
  j["sim_time_s"] = r.sim_time_s;
  j["wall_time_s"] = r.wall_time_s;
  j["frames"] = r.frames;
  j["global_registrations"] = r.global_registrations;
  j["perception_ms_median"] = r.perception_ms_median;
  j["render_ms_median"] = r.render_ms_median;
  return j;
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::trunc);
  file << text;
  if (!file) throw std::runtime_error(path.string() + ": cannot write");
}

std::string Describe(const MissionResult& r) {
  return fmt::format(
      "{}; grasped at {}, pose RMSE {}, {} switch(es), {} safe-volume entr{}, {:.2f}x real time",
      r.success ? "success" : "FAILED: " + r.failure,
      r.time_to_grasp_s >= 0 ? fmt::format("{:.1f} s", r.time_to_grasp_s) : "never",
      r.pose_rmse_m >= 0 ? fmt::format("{:.1f} mm", 1e3 * r.pose_rmse_m) : "n/a", r.grasp_switches,
      r.safe_volume_entries, r.safe_volume_entries == 1 ? "y" : "ies", r.realtime_factor);
}

}  // namespace

void AddMissionOptions(CLI::App* cmd, MissionCommandOptions* o) {
  MissionOptions& m = o->mission;
  cmd->add_option("--out", o->out_dir, "Report folder: index.html, summary.json, mission.log")
      ->required();
  cmd->add_option("--seed", m.seed, "World seed (same seed, same mission)")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--runs", o->runs,
                  "Fly this many seeded missions (seed, seed+1, ...) and report the success rate")
      ->capture_default_str()
      ->check(cli::Range(1, 100000));
  cmd->add_option("--object", m.object,
                  "Object: a shipped name (crawler, u_shape, pipe) or a model path [crawler]");
  cmd->add_option("--arm", m.arm_type, "Arms")
      ->capture_default_str()
      ->check(CLI::IsMember({"4dof", "6dof"}));
  cmd->add_option("--sway", m.sway_amplitude_m,
                  "Hover sway amplitude per horizontal axis, m [world: 0.03]")
      ->check(cli::Range(0.0, 1.0));
  cmd->add_option("--sway-hz", m.sway_frequency_hz, "Hover sway frequency, Hz [world: 0.5]")
      ->check(cli::Range(0.0, 5.0));
  cmd->add_option("--motion", m.motion, "Object motion along the pipe [world: crawl]")
      ->check(CLI::IsMember({"static", "crawl"}));
  cmd->add_option("--speed", m.object_speed_mps, "Crawl speed, m/s [world: 0.03]")
      ->check(cli::Range(0.0, 1.0));
  cmd->add_option("--config", m.config_path, "Mission YAML [data/config/mission_default.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_option("--hardware", m.hardware_path,
                  "Hardware YAML (e.g. data/config/hardware_sim.yaml: the real drivers against "
                  "simulated devices) "
                  "[every device simulated in-process]")
      ->check(CLI::ExistingFile);
  cmd->add_option("--timeout", m.timeout_s, "Mission time limit, s [mission config: 180]")
      ->check(cli::Range(1.0, 3600.0));
}

namespace {

ReportRow Headline(const MissionResult& r) {
  const auto or_none = [](double v, const std::string& text) {
    return v >= 0 ? text : std::string("n/a");
  };
  return {
      {"success", r.success ? "yes" : "no: " + r.failure},
      {"time to grasp", or_none(r.time_to_grasp_s, fmt::format("{:.2f} s", r.time_to_grasp_s))},
      {"object position RMSE",
       or_none(r.pose_rmse_m, fmt::format("{:.2f} mm", 1e3 * r.pose_rmse_m))},
      {"object rotation RMSE",
       or_none(r.rotation_rmse_deg, fmt::format("{:.2f} deg", r.rotation_rmse_deg))},
      {"grasp switches", std::to_string(r.grasp_switches)},
      {"grasp attempts", std::to_string(r.attempts)},
      {"safe-volume entries", std::to_string(r.safe_volume_entries)},
      {"emergency stops", std::to_string(r.emergency_stops)},
      {"mission time", fmt::format("{:.1f} s simulated in {:.1f} s ({:.2f}x real time)",
                                   r.sim_time_s, r.wall_time_s, r.realtime_factor)},
      {"camera frames",
       fmt::format("{} (perception {:.1f} ms, rendering {:.1f} ms median; {} with a global "
                   "registration)",
                   r.frames, r.perception_ms_median, r.render_ms_median, r.global_registrations)}};
}

ReportRow RunRow(std::uint64_t seed, const MissionResult& r) {
  return {{"seed", std::to_string(seed)},
          {"success", r.success ? "yes" : "no"},
          {"time to grasp (s)",
           r.time_to_grasp_s >= 0 ? fmt::format("{:.1f}", r.time_to_grasp_s) : "-"},
          {"pose RMSE (mm)", r.pose_rmse_m >= 0 ? fmt::format("{:.1f}", 1e3 * r.pose_rmse_m) : "-"},
          {"switches", std::to_string(r.grasp_switches)},
          {"safe-volume entries", std::to_string(r.safe_volume_entries)},
          {"real-time factor", fmt::format("{:.2f}", r.realtime_factor)},
          {"failure", r.failure}};
}

}  // namespace

int RunMissionCommand(const MissionCommandOptions& options, std::ostream& out, std::ostream& err) {
  const fs::path dir(options.out_dir);
  fs::create_directories(dir);
  nlohmann::json summary;
  summary["object"] = options.mission.object.empty() ? "crawler" : options.mission.object;
  summary["arm"] = options.mission.arm_type;
  MissionRecord record;  // of the first run: the report's plots

  if (options.runs == 1) {
    std::ostringstream log;
    struct Tee : std::streambuf {
      std::ostream *a, *b;
      int overflow(int c) override {
        a->put(static_cast<char>(c));
        b->put(static_cast<char>(c));
        return c;
      }
    } tee;
    tee.a = &out;
    tee.b = &log;
    std::ostream both(&tee);
    out << fmt::format("mission: seed {}, {} arms, report in {}\n", options.mission.seed,
                       options.mission.arm_type, dir.string());
    MissionResult result;
    try {
      result = RunMission(options.mission, &record, &both);
    } catch (...) {
      WriteText(dir / "mission.log", log.str());
      throw;
    }
    WriteText(dir / "mission.log", log.str());
    summary.update(RunJson(options.mission.seed, result));
    const std::string path = WriteSummaryFile(dir.string(), summary.dump(2));
    WriteMissionReport(record, record.object_mesh_o, Headline(result), {}, dir.string());
    out << "mission: " << Describe(result) << "\n";
    out << "Wrote " << (dir / "index.html").string() << ", " << path << " and "
        << (dir / "mission.log").string() << "\n";
    return result.success ? kExitOk : kExitMissionFailed;
  }

  fs::create_directories(dir / "logs");
  Progress progress(err, "missions", options.runs, "missions");
  nlohmann::json runs = nlohmann::json::array();
  std::vector<ReportRow> rows;
  int successes = 0, with_switch = 0, recovered_by_switch = 0, entries = 0;
  double sum_time = 0.0;
  std::vector<double> factors;  // real-time factor of each run
  for (int k = 0; k < options.runs; ++k) {
    MissionOptions m = options.mission;
    m.seed = options.mission.seed + static_cast<std::uint64_t>(k);
    std::ostringstream log;
    MissionResult result;
    try {
      result = RunMission(m, k == 0 ? &record : nullptr, &log);
    } catch (const std::exception& e) {
      result.failure = std::string("error: ") + e.what();
    }
    WriteText(dir / "logs" / fmt::format("seed_{}.log", m.seed), log.str());
    runs.push_back(RunJson(m.seed, result));
    rows.push_back(RunRow(m.seed, result));
    successes += result.success;
    with_switch += result.grasp_switches > 0;
    recovered_by_switch += result.success && result.grasp_switches > 0;
    entries += result.safe_volume_entries;
    factors.push_back(result.realtime_factor);
    if (result.success) sum_time += result.time_to_grasp_s;
    if (!result.success) err << fmt::format("\nseed {}: {}\n", m.seed, Describe(result));
    progress.Update(k + 1);
  }
  progress.Finish();
  const double min_factor = Percentile(factors, 0.0), median_factor = Percentile(factors, 0.5);
  summary["runs"] = runs;
  summary["success_rate"] = double(successes) / options.runs;
  summary["successes"] = successes;
  summary["runs_with_switch"] = with_switch;
  summary["successes_after_switch"] = recovered_by_switch;
  summary["safe_volume_entries"] = entries;
  summary["realtime_factor_min"] = min_factor;
  summary["realtime_factor_median"] = median_factor;
  summary["time_to_grasp_s_mean"] = successes > 0 ? sum_time / successes : 0.0;
  const std::string path = WriteSummaryFile(dir.string(), summary.dump(2));
  const ReportRow headline = {
      {"runs", fmt::format("{} (seeds {} to {})", options.runs, options.mission.seed,
                           options.mission.seed + options.runs - 1)},
      {"success rate", fmt::format("{:.1f} % ({} of {})", 100.0 * successes / options.runs,
                                   successes, options.runs)},
      {"runs with a grasp switch",
       fmt::format("{} ({} of them succeeded)", with_switch, recovered_by_switch)},
      {"safe-volume entries", std::to_string(entries)},
      {"real-time factor",
       fmt::format("{:.2f} median, {:.2f} the slowest", median_factor, min_factor)},
      {"plots", fmt::format("of the first run (seed {}); every run's log is in logs/",
                            options.mission.seed)}};
  WriteMissionReport(record, record.object_mesh_o, headline, rows, dir.string());
  out << fmt::format(
      "missions: {} of {} succeeded ({:.1f} %), {} with a grasp switch ({} of them succeeded), {} "
      "safe-volume "
      "entries, {:.2f}x real time median ({:.2f}x the slowest)\n",
      successes, options.runs, 100.0 * successes / options.runs, with_switch, recovered_by_switch,
      entries, median_factor, min_factor);
  out << "Wrote " << (dir / "index.html").string() << " and " << path << "\n";
  return successes == options.runs ? kExitOk : kExitMissionFailed;
}

}  // namespace aerograsp
