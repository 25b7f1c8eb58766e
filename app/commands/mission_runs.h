// Seeded missions flown one after another, and their report: the mission
// command's --runs and the missions benchmark (app/benchmarks/mission_benchmark.h)
// fly and report them the same way. The report folder holds summary.json
// (every run and the figures of app/report/mission_statistics.h), index.html
// (the figures, one row per run and the plots of the first run) and
// logs/seed_N.log (every run's log).
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "app/report/mission_statistics.h"
#include "app/runtime/mission_record.h"
#include "app/runtime/mission_runner.h"
#include "telemetry/telemetry_config.h"

namespace aerograsp {

/// The missions flown, in seed order.
struct MissionRuns {
  std::vector<std::uint64_t> seeds;
  std::vector<MissionResult> results;
  MissionRecord record;  ///< of the first run: the report's plots
};

/// Flies `runs` missions of `options` on seeds options.seed, +1, ... and
/// writes each one's log to dir/logs/seed_N.log. They share one MissionSetup
/// (options.setup when given): the planner is built and the placement searched
/// once. `telemetry` (may be null)
/// is opened for the first run only (dir/mission.mcap). A mission that throws
/// is a failed run whose failure says "error: " and why. `after_each` (may be
/// empty) hears each run as it ends, with its seed.
/// @throws std::runtime_error naming a log that cannot be written.
MissionRuns FlyMissionRuns(
    const MissionOptions& options, int runs, const std::string& dir,
    const TelemetryConfig* telemetry,
    const std::function<void(std::uint64_t seed, const MissionResult&)>& after_each);

/// Writes dir/summary.json (`summary` with "runs", every run, and the
/// statistics' keys added) and dir/index.html; returns the statistics.
/// @throws std::runtime_error naming the file that cannot be written.
MissionStatistics WriteMissionRunsReport(const MissionRuns& runs, nlohmann::json summary,
                                         const std::string& dir);

}  // namespace aerograsp
