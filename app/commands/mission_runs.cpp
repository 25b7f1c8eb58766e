#include "app/commands/mission_runs.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/commands/telemetry_options.h"
#include "app/report/mission_report.h"
#include "app/report/summary_file.h"
#include "app/runtime/mission_setup.h"

namespace aerograsp {

namespace fs = std::filesystem;

MissionRuns FlyMissionRuns(
    const MissionOptions& options, int runs, const std::string& dir,
    const TelemetryConfig* telemetry_config,
    const std::function<void(std::uint64_t seed, const MissionResult&)>& after_each) {
  const fs::path logs = fs::path(dir) / "logs";
  fs::create_directories(logs);
  MissionRuns flown;
  // The runs differ only in their seed: the first builds the planner and
  // searches the placement, the others reuse them (app/runtime/mission_setup.h).
  const std::shared_ptr<MissionSetup> setup =
      options.setup ? options.setup : std::make_shared<MissionSetup>();
  for (int k = 0; k < runs; ++k) {
    MissionOptions m = options;
    m.setup = setup;
    m.seed = options.seed + static_cast<std::uint64_t>(k);
    std::ostringstream log;
    CommandTelemetry telemetry;  // the first run's, as its plots
    if (k == 0 && telemetry_config) {
      telemetry = OpenTelemetry(*telemetry_config, dir, "mission", [&log](const std::string& line) {
        log << "telemetry: " << line << "\n";
      });
    }
    MissionLinks links;
    links.telemetry = telemetry.sink();
    links.emergency_stop = telemetry.emergency_stop.get();
    MissionResult result;
    try {
      result = RunMission(m, k == 0 ? &flown.record : nullptr, &log, links);
    } catch (const std::exception& e) {
      // The runs share their configuration, object, arms and setup: an error
      // in the first is an error in every one, and no run flew.
      if (k == 0) throw;
      result.failure = std::string("error: ") + e.what();
    }
    const std::string mcap = telemetry.Close();
    if (!mcap.empty()) log << "Wrote " << mcap << "\n";
    const fs::path log_path = logs / fmt::format("seed_{}.log", m.seed);
    std::ofstream file(log_path, std::ios::trunc);
    file << log.str();
    if (!file) throw std::runtime_error(log_path.string() + ": cannot write");
    flown.seeds.push_back(m.seed);
    flown.results.push_back(result);
    if (after_each) after_each(m.seed, result);
  }
  return flown;
}

MissionStatistics WriteMissionRunsReport(const MissionRuns& flown, nlohmann::json summary,
                                         const std::string& dir) {
  nlohmann::json runs = nlohmann::json::array();
  std::vector<ReportRow> rows;
  for (std::size_t k = 0; k < flown.results.size(); ++k) {
    runs.push_back(MissionRunJson(flown.seeds[k], flown.results[k]));
    rows.push_back(MissionRunRow(flown.seeds[k], flown.results[k]));
  }
  const MissionStatistics statistics = SummarizeMissions(flown.results);
  summary["runs"] = runs;
  summary.update(MissionStatisticsJson(statistics));
  WriteSummaryFile(dir, summary.dump(2));
  ReportRow headline;
  if (!flown.seeds.empty()) {
    headline.push_back({"runs", fmt::format("{} (seeds {} to {})", flown.seeds.size(),
                                            flown.seeds.front(), flown.seeds.back())});
  }
  for (auto& row : MissionStatisticsRows(statistics)) headline.push_back(std::move(row));
  if (!flown.seeds.empty()) {
    headline.push_back(
        {"plots", fmt::format("of the first run (seed {}); every run's log is in logs/",
                              flown.seeds.front())});
  }
  WriteMissionReport(flown.record, flown.record.object_mesh_o, headline, rows, dir);
  return statistics;
}

}  // namespace aerograsp
