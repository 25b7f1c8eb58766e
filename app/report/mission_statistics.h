// The figures of one or more simulated missions (app/runtime/mission_runner.h):
// success on the first attempt and within three, the attempts each run took,
// time to grasp, the gripper closes and where they met the true object, the
// estimate's error while grasping, the servo cycle, the real-time factor and
// the safety counts. The mission command's summary.json, its printed summary
// and its index.html all take them from here.
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "app/report/mission_report.h"
#include "app/runtime/mission_runner.h"

namespace aerograsp {

/// Runs that took a given number of grasp attempts, and how many of them succeeded.
struct AttemptCount {
  int runs = 0;
  int successes = 0;
};

/// The figures over a set of missions. Figures with no sample (no success, no
/// close, no frame while grasping) are NaN.
struct MissionStatistics {
  int runs = 0;
  int successes = 0;
  int first_attempt_successes = 0;  ///< succeeded with one grasp attempt
  int successes_within_3 = 0;       ///< succeeded with at most three attempts
  /// By grasp attempts (MissionResult::attempts): the runs and their successes.
  std::map<int, AttemptCount> attempts;
  /// From the start to both grippers holding, over the successful runs, s.
  double time_to_grasp_median_s = NAN;
  double time_to_grasp_p90_s = NAN;
  double time_to_grasp_mean_s = NAN;
  int closes = 0;  ///< gripper closes in all runs
  int holds = 0;   ///< ... after which the gripper held the object
  /// The tool against its grasp on the true object at contact, over every
  /// close of every run, m.
  double tool_error_median_m = NAN;
  double tool_error_p90_m = NAN;
  /// The object position estimate against the truth over every frame counted
  /// while grasping in every run (each run's RMSE weighted by its frames), m.
  double pose_rmse_m = NAN;
  /// The longest servo cycle of all runs, wall time and thread CPU time, ms.
  double servo_step_ms_max = 0.0;
  double servo_step_cpu_ms_max = 0.0;
  double realtime_factor_min = 0.0;
  double realtime_factor_median = 0.0;
  /// The same on the missions' CPU time (MissionResult::realtime_factor_cpu).
  double realtime_factor_cpu_min = 0.0;
  double realtime_factor_cpu_median = 0.0;
  int safe_volume_entries = 0;
  int arm_contacts = 0;
  int emergency_stops = 0;
  int runs_with_switch = 0;        ///< runs whose followed grasp was switched
  int successes_after_switch = 0;  ///< ... that succeeded

  double success_rate() const { return runs > 0 ? double(successes) / runs : 0.0; }
  double first_attempt_rate() const {
    return runs > 0 ? double(first_attempt_successes) / runs : 0.0;
  }
  double within_3_rate() const { return runs > 0 ? double(successes_within_3) / runs : 0.0; }
};

/// The figures of `runs` (any number, none included).
MissionStatistics SummarizeMissions(const std::vector<MissionResult>& runs);

/// One run's entry of summary.json: its result, its closes and their figures.
nlohmann::json MissionRunJson(std::uint64_t seed, const MissionResult& result);

/// The figures as summary.json keys (NaN figures as null).
nlohmann::json MissionStatisticsJson(const MissionStatistics& s);

/// The figures as lines of text for the terminal, each ending in a newline;
/// the first says "<successes> of <runs> succeeded".
std::string DescribeMissionStatistics(const MissionStatistics& s);

/// The figures as rows (name, value) of the report's headline table.
ReportRow MissionStatisticsRows(const MissionStatistics& s);

/// The main figures as short (column, value) cells: one row of a table that
/// compares sets of missions (the missions benchmark). Every set gives the
/// same columns in the same order.
ReportRow MissionStatisticsColumns(const MissionStatistics& s);

/// One run as (column, value) cells of the report's table of runs.
ReportRow MissionRunRow(std::uint64_t seed, const MissionResult& r);

/// One run in a line: success or why not, time to grasp, attempts, closes,
/// tool error at contact, pose RMSE, switches, safety counts, worst servo
/// step and real-time factor.
std::string DescribeMissionRun(const MissionResult& r);

}  // namespace aerograsp
