#include "app/benchmarks/mission_benchmark.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli_checks.h"
#include "app/commands/mission_runs.h"
#include "app/exit_codes.h"
#include "app/report/mission_statistics.h"
#include "app/report/report_folder.h"
#include "app/report/report_html.h"
#include "app/report/summary_file.h"
#include "core/config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using WallClock = std::chrono::steady_clock;

std::vector<std::string> ConfigNames() {
  std::vector<std::string> names;
  for (const MissionBenchmarkConfig& c : MissionBenchmarkConfigs()) names.push_back(c.name());
  return names;
}

/// The configurations asked for, in the benchmark's order.
std::vector<MissionBenchmarkConfig> Chosen(const std::vector<std::string>& names) {
  const std::vector<MissionBenchmarkConfig> all = MissionBenchmarkConfigs();
  for (const std::string& name : names) {
    const bool known = std::any_of(
        all.begin(), all.end(), [&](const MissionBenchmarkConfig& c) { return c.name() == name; });
    if (!known) {
      std::string list;
      for (const std::string& n : ConfigNames()) list += (list.empty() ? "" : ", ") + n;
      throw ConfigError(fmt::format("--configs: '{}' is not one of {}", name, list));
    }
  }
  if (names.empty()) return all;
  std::vector<MissionBenchmarkConfig> chosen;
  for (const MissionBenchmarkConfig& c : all) {
    if (std::find(names.begin(), names.end(), c.name()) != names.end()) chosen.push_back(c);
  }
  return chosen;
}

/// Rows of text under a header, each column as wide as its widest cell.
std::string TextTable(const std::vector<std::string>& header,
                      const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = header[c].size();
    for (const auto& row : rows) width[c] = std::max(width[c], row[c].size());
  }
  const auto line = [&](const std::vector<std::string>& cells) {
    std::string text;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      // The first column (the name) left-aligned, the figures right-aligned.
      text += c == 0 ? fmt::format("{:<{}}", cells[c], width[c])
                     : fmt::format("  {:>{}}", cells[c], width[c]);
    }
    return text + "\n";
  };
  std::string text = line(header);
  for (const auto& row : rows) text += line(row);
  return text;
}

std::string Remaining(double seconds) {
  const int s = static_cast<int>(seconds + 0.5);
  return s >= 3600 ? fmt::format("{}h{:02}m", s / 3600, s % 3600 / 60)
                   : fmt::format("{}m{:02}s", s / 60, s % 60);
}

}  // namespace

std::vector<MissionBenchmarkConfig> MissionBenchmarkConfigs() {
  std::vector<MissionBenchmarkConfig> configs;
  for (const char* arm : {"4dof", "6dof"})
    for (const char* object : {"crawler", "pipe", "u_shape"})
      for (const char* motion : {"crawl", "static"}) configs.push_back({arm, object, motion});
  return configs;  // 4dof-crawler-crawl, the default, first
}

void AddMissionBenchmarkOptions(CLI::App* cmd, MissionBenchmarkOptions* o) {
  cmd->add_option("--out", o->out_dir,
                  "Report folder: summary.json, index.html, one folder per configuration")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--runs-default", o->runs_default,
                  "Seeds of the default configuration (4dof-crawler-crawl)")
      ->capture_default_str()
      ->check(cli::Range(1, 100000));
  cmd->add_option("--runs", o->runs, "Seeds of each other configuration")
      ->capture_default_str()
      ->check(cli::Range(1, 100000));
  cmd->add_option("--seed", o->seed, "First seed of every configuration (then +1, +2, ...)")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--configs", o->configs,
                  "Configurations to fly, ARM-OBJECT-MOTION (e.g. 6dof-pipe-static) [all twelve]")
      ->check(CLI::IsMember(ConfigNames()));
  cmd->add_option("--config", o->config_path, "Mission YAML [data/config/mission_default.yaml]")
      ->check(CLI::ExistingFile);
  cmd->add_option("--timeout", o->timeout_s, "Mission time limit, s [mission config: 180]")
      ->check(cli::Range(1.0, 3600.0));
}

int RunMissionBenchmark(const MissionBenchmarkOptions& options, std::ostream& out,
                        std::ostream& err) {
  const std::vector<MissionBenchmarkConfig> configs = Chosen(options.configs);
  const auto runs_of = [&](const MissionBenchmarkConfig& c) {
    return c.name() == MissionBenchmarkConfigs().front().name() ? options.runs_default
                                                                : options.runs;
  };
  int total = 0;
  for (const MissionBenchmarkConfig& c : configs) total += runs_of(c);
  ReportFolder folder(options.out_dir, options.overwrite);
  out << fmt::format(
      "benchmark missions: {} configurations, {} missions from seed {} (the default on {}, the "
      "others on {} seeds)\n",
      configs.size(), total, options.seed, options.runs_default, options.runs);

  const WallClock::time_point start = WallClock::now();
  int done = 0, failed = 0;
  std::vector<std::string> header = {"configuration"};
  std::vector<std::vector<std::string>> rows;
  nlohmann::json per_config = nlohmann::json::array();
  for (const MissionBenchmarkConfig& c : configs) {
    MissionOptions m;
    m.config_path = options.config_path;
    m.seed = options.seed;
    m.arm_type = c.arm;
    m.object = c.object;
    m.motion = c.motion;
    m.timeout_s = options.timeout_s;
    const std::string dir = (fs::path(folder.path()) / c.name()).string();
    const int runs = runs_of(c);
    int k = 0;
    const MissionRuns flown =
        FlyMissionRuns(m, runs, dir, nullptr, [&](std::uint64_t seed, const MissionResult& r) {
          ++done;
          ++k;
          failed += !r.success;
          const double elapsed = std::chrono::duration<double>(WallClock::now() - start).count();
          err << fmt::format(
                     "  [{}/{}] {} {}/{} seed {}: {}, {:.1f}x real time ({:.1f}x on CPU "
                     "time); {} left\n",
                     done, total, c.name(), k, runs, seed,
                     r.success ? fmt::format("grasped at {:.1f} s after {} attempt(s)",
                                             r.time_to_grasp_s, r.attempts)
                               : "FAILED: " + r.failure,
                     r.realtime_factor, r.realtime_factor_cpu,
                     Remaining(elapsed / done * (total - done)))
              << std::flush;
        });
    nlohmann::json summary = {
        {"configuration", c.name()}, {"arm", c.arm}, {"object", c.object}, {"motion", c.motion}};
    const MissionStatistics s = WriteMissionRunsReport(flown, summary, dir);
    const ReportRow columns = MissionStatisticsColumns(s);
    std::vector<std::string> row = {c.name()};
    for (const auto& [name, value] : columns) {
      if (rows.empty()) header.push_back(name);
      row.push_back(value);
    }
    rows.push_back(row);
    out << c.name() << "\n" << DescribeMissionStatistics(s) << std::flush;
    nlohmann::json entry = summary;
    entry["runs"] = runs;
    entry["seeds"] = {options.seed, options.seed + static_cast<std::uint64_t>(runs) - 1};
    entry["report"] = c.name() + "/index.html";
    entry.update(MissionStatisticsJson(s));
    per_config.push_back(entry);
  }

  const std::string table = TextTable(header, rows);
  out << "\n" << table;
  const nlohmann::json summary = {
      {"stage", "missions"},         {"seed", options.seed}, {"runs_default", options.runs_default},
      {"runs", options.runs},        {"missions", total},    {"failed", failed},
      {"configurations", per_config}};
  WriteSummaryFile(folder.path(), summary.dump(2));
  std::ostringstream page;
  BeginHtmlPage("Missions benchmark", page);
  page << "<p>" << total << " simulated missions from seed " << options.seed
       << "; each configuration's missions, their plots and logs are in its own report:</p>\n";
  WriteHtmlTable(header, rows, page);
  page << "<ul>\n";
  for (const MissionBenchmarkConfig& c : configs) {
    page << "<li><a href=\"" << EscapeHtml(c.name()) << "/index.html\">" << EscapeHtml(c.name())
         << "</a></li>\n";
  }
  page << "</ul>\n";
  WriteHtmlPage(page.str(), folder.path());
  out << "Wrote " << folder.Commit() << "/summary.json and index.html\n";
  return failed == 0 ? kExitOk : kExitMissionFailed;
}

}  // namespace aerograsp
