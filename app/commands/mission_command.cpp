#include "app/commands/mission_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/cli_checks.h"
#include "app/exit_codes.h"
#include "app/report/mission_report.h"
#include "app/report/mission_statistics.h"
#include "app/report/progress.h"
#include "app/report/summary_file.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::trunc);
  file << text;
  if (!file) throw std::runtime_error(path.string() + ": cannot write");
}

std::string Describe(const MissionResult& r) {
  const MissionStatistics s = SummarizeMissions({r});
  return fmt::format(
      "{}; grasped at {} after {} attempt(s), {} gripper close(s) ({} held), tool to the true "
      "grasp at contact {} median, pose RMSE {}, {} switch(es), {} safe-volume entr{}, {} arm "
      "contact(s), worst servo step {:.2f} ms, {:.2f}x real time",
      r.success ? "success" : "FAILED: " + r.failure,
      r.time_to_grasp_s >= 0 ? fmt::format("{:.1f} s", r.time_to_grasp_s) : "never", r.attempts,
      s.closes, s.holds,
      std::isfinite(s.tool_error_median_m) ? fmt::format("{:.1f} mm", 1e3 * s.tool_error_median_m)
                                           : "n/a",
      r.pose_rmse_m >= 0 ? fmt::format("{:.1f} mm", 1e3 * r.pose_rmse_m) : "n/a", r.grasp_switches,
      r.safe_volume_entries, r.safe_volume_entries == 1 ? "y" : "ies", r.arm_contacts,
      r.servo_step_ms_max, r.realtime_factor);
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
  AddTelemetryOptions(cmd, &o->telemetry);
}

namespace {

ReportRow Headline(const MissionResult& r) {
  const auto or_none = [](double v, const std::string& text) {
    return v >= 0 ? text : std::string("n/a");
  };
  const MissionStatistics s = SummarizeMissions({r});
  return {
      {"success", r.success ? "yes" : "no: " + r.failure},
      {"time to grasp", or_none(r.time_to_grasp_s, fmt::format("{:.2f} s", r.time_to_grasp_s))},
      {"grasp attempts", std::to_string(r.attempts)},
      {"gripper closes", fmt::format("{} ({} held)", s.closes, s.holds)},
      {"tool to the true grasp at contact",
       std::isfinite(s.tool_error_median_m)
           ? fmt::format("median {:.1f} mm, 90th percentile {:.1f} mm", 1e3 * s.tool_error_median_m,
                         1e3 * s.tool_error_p90_m)
           : "n/a"},
      {"object position RMSE while grasping",
       or_none(r.pose_rmse_m, fmt::format("{:.2f} mm", 1e3 * r.pose_rmse_m))},
      {"object rotation RMSE while grasping",
       or_none(r.rotation_rmse_deg, fmt::format("{:.2f} deg", r.rotation_rmse_deg))},
      {"grasp switches", std::to_string(r.grasp_switches)},
      {"safe-volume entries", std::to_string(r.safe_volume_entries)},
      {"arm contacts", std::to_string(r.arm_contacts)},
      {"emergency stops", std::to_string(r.emergency_stops)},
      {"worst servo step", fmt::format("{:.2f} ms ({:.2f} ms thread CPU)", r.servo_step_ms_max,
                                       r.servo_step_cpu_ms_max)},
      {"mission time", fmt::format("{:.1f} s simulated in {:.1f} s ({:.2f}x real time)",
                                   r.sim_time_s, r.wall_time_s, r.realtime_factor)},
      {"camera frames",
       fmt::format("{} (perception {:.1f} ms, rendering {:.1f} ms median; {} with a global "
                   "registration)",
                   r.frames, r.perception_ms_median, r.render_ms_median, r.global_registrations)}};
}

ReportRow RunRow(std::uint64_t seed, const MissionResult& r) {
  const MissionStatistics s = SummarizeMissions({r});
  return {{"seed", std::to_string(seed)},
          {"success", r.success ? "yes" : "no"},
          {"attempts", std::to_string(r.attempts)},
          {"time to grasp (s)",
           r.time_to_grasp_s >= 0 ? fmt::format("{:.1f}", r.time_to_grasp_s) : "-"},
          {"closes (held)", fmt::format("{} ({})", s.closes, s.holds)},
          {"tool at contact, median (mm)", std::isfinite(s.tool_error_median_m)
                                               ? fmt::format("{:.1f}", 1e3 * s.tool_error_median_m)
                                               : "-"},
          {"pose RMSE (mm)", r.pose_rmse_m >= 0 ? fmt::format("{:.1f}", 1e3 * r.pose_rmse_m) : "-"},
          {"switches", std::to_string(r.grasp_switches)},
          {"safe-volume entries", std::to_string(r.safe_volume_entries)},
          {"arm contacts", std::to_string(r.arm_contacts)},
          {"worst servo step (ms)", fmt::format("{:.2f}", r.servo_step_ms_max)},
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
  const TelemetryConfig telemetry_config = LoadTelemetryConfig(options.telemetry);

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
    CommandTelemetry telemetry =
        OpenTelemetry(telemetry_config, dir.string(), "mission",
                      [&both](const std::string& line) { both << "telemetry: " << line << "\n"; });
    MissionLinks links;
    links.telemetry = telemetry.sink();
    links.emergency_stop = telemetry.emergency_stop.get();
    MissionResult result;
    try {
      result = RunMission(options.mission, &record, &both, links);
    } catch (...) {
      telemetry.Close();
      WriteText(dir / "mission.log", log.str());
      throw;
    }
    const std::string mcap = telemetry.Close();
    WriteText(dir / "mission.log", log.str());
    summary.update(MissionRunJson(options.mission.seed, result));
    const std::string path = WriteSummaryFile(dir.string(), summary.dump(2));
    WriteMissionReport(record, record.object_mesh_o, Headline(result), {}, dir.string());
    out << "mission: " << Describe(result) << "\n";
    out << "Wrote " << (dir / "index.html").string() << ", " << path << " and "
        << (dir / "mission.log").string() << "\n";
    if (!mcap.empty()) out << "Wrote " << mcap << "\n";
    return result.success ? kExitOk : kExitMissionFailed;
  }

  fs::create_directories(dir / "logs");
  Progress progress(err, "missions", options.runs, "missions");
  nlohmann::json runs = nlohmann::json::array();
  std::vector<ReportRow> rows;
  std::vector<MissionResult> results;
  for (int k = 0; k < options.runs; ++k) {
    MissionOptions m = options.mission;
    m.seed = options.mission.seed + static_cast<std::uint64_t>(k);
    std::ostringstream log;
    CommandTelemetry telemetry;  // the first run's, as its plots
    if (k == 0) {
      telemetry =
          OpenTelemetry(telemetry_config, dir.string(), "mission",
                        [&log](const std::string& line) { log << "telemetry: " << line << "\n"; });
    }
    MissionLinks links;
    links.telemetry = telemetry.sink();
    links.emergency_stop = telemetry.emergency_stop.get();
    MissionResult result;
    try {
      result = RunMission(m, k == 0 ? &record : nullptr, &log, links);
    } catch (const std::exception& e) {
      result.failure = std::string("error: ") + e.what();
    }
    const std::string mcap = telemetry.Close();
    if (!mcap.empty()) log << "Wrote " << mcap << "\n";
    WriteText(dir / "logs" / fmt::format("seed_{}.log", m.seed), log.str());
    runs.push_back(MissionRunJson(m.seed, result));
    rows.push_back(RunRow(m.seed, result));
    results.push_back(result);
    if (!result.success) err << fmt::format("\nseed {}: {}\n", m.seed, Describe(result));
    progress.Update(k + 1);
  }
  progress.Finish();
  const MissionStatistics statistics = SummarizeMissions(results);
  summary["runs"] = runs;
  summary.update(MissionStatisticsJson(statistics));
  const std::string path = WriteSummaryFile(dir.string(), summary.dump(2));
  ReportRow headline = {
      {"runs", fmt::format("{} (seeds {} to {})", options.runs, options.mission.seed,
                           options.mission.seed + options.runs - 1)}};
  for (auto& row : MissionStatisticsRows(statistics)) headline.push_back(std::move(row));
  headline.push_back(
      {"plots", fmt::format("of the first run (seed {}); every run's log is in logs/",
                            options.mission.seed)});
  WriteMissionReport(record, record.object_mesh_o, headline, rows, dir.string());
  out << DescribeMissionStatistics(statistics);
  out << "Wrote " << (dir / "index.html").string() << " and " << path << "\n";
  const int successes = statistics.successes;
  return successes == options.runs ? kExitOk : kExitMissionFailed;
}

}  // namespace aerograsp
