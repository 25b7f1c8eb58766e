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
#include "app/commands/mission_runs.h"
#include "app/exit_codes.h"
#include "app/report/mission_report.h"
#include "app/report/mission_statistics.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "app/report/summary_file.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::trunc);
  file << text;
  if (!file) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

void AddMissionOptions(CLI::App* cmd, MissionCommandOptions* o) {
  MissionOptions& m = o->mission;
  cmd->add_option("--out", o->out_dir, "Report folder: index.html, summary.json, mission.log")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
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
      {"mission time",
       fmt::format(
           "{:.1f} s simulated in {:.1f} s ({:.2f}x real time; {:.1f} s of CPU time, {:.2f}x)",
           r.sim_time_s, r.wall_time_s, r.realtime_factor, r.cpu_time_s, r.realtime_factor_cpu)},
      {"camera frames",
       fmt::format("{} (perception {:.1f} ms, rendering {:.1f} ms median; {} with a global "
                   "registration)",
                   r.frames, r.perception_ms_median, r.render_ms_median, r.global_registrations)}};
}

}  // namespace

int RunMissionCommand(const MissionCommandOptions& options, std::ostream& out, std::ostream& err) {
  ReportFolder folder(options.out_dir, options.overwrite);
  const fs::path dir(folder.path());
  nlohmann::json summary;
  summary["object"] = options.mission.object.empty() ? "crawler" : options.mission.object;
  summary["arm"] = options.mission.arm_type;
  const TelemetryConfig telemetry_config = LoadTelemetryConfig(options.telemetry);

  if (options.runs == 1) {
    MissionRecord record;  // the report's plots
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
                       options.mission.arm_type, folder.final_path());
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
      throw;  // the earlier report, if any, stays whole
    }
    const std::string mcap = telemetry.Close();
    WriteText(dir / "mission.log", log.str());
    summary.update(MissionRunJson(options.mission.seed, result));
    const std::string path = WriteSummaryFile(dir.string(), summary.dump(2));
    WriteMissionReport(record, record.object_mesh_o, Headline(result), {}, dir.string());
    folder.Commit();
    out << "mission: " << DescribeMissionRun(result) << "\n";
    out << "Wrote " << folder.Final((dir / "index.html").string()) << ", " << folder.Final(path)
        << " and " << folder.Final((dir / "mission.log").string()) << "\n";
    if (!mcap.empty()) out << "Wrote " << folder.Final(mcap) << "\n";
    return result.success ? kExitOk : kExitMissionFailed;
  }

  Progress progress(err, "missions", options.runs, "missions");
  int done = 0;
  const MissionRuns flown =
      FlyMissionRuns(options.mission, options.runs, dir.string(), &telemetry_config,
                     [&](std::uint64_t seed, const MissionResult& result) {
                       if (!result.success)
                         err << fmt::format("\nseed {}: {}\n", seed, DescribeMissionRun(result));
                       progress.Update(++done);
                     });
  progress.Finish();
  const MissionStatistics statistics = WriteMissionRunsReport(flown, summary, dir.string());
  folder.Commit();
  out << DescribeMissionStatistics(statistics);
  out << "Wrote " << folder.final_path() << "/index.html and " << folder.final_path()
      << "/summary.json"
      << "\n";
  const int successes = statistics.successes;
  return successes == options.runs ? kExitOk : kExitMissionFailed;
}

}  // namespace aerograsp
