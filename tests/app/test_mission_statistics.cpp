#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "app/report/mission_statistics.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

MissionResult Result(bool success, int attempts, double time_to_grasp_s) {
  MissionResult r;
  r.success = success;
  r.failure = success ? "" : "every grasp attempt failed";
  r.attempts = attempts;
  r.time_to_grasp_s = success ? time_to_grasp_s : -1.0;
  r.realtime_factor = 5.0;
  return r;
}

GripperClose Close(int arm, bool holds, double tool_error_m) {
  GripperClose c;
  c.arm = arm;
  c.holds = holds;
  c.tool_error_m = tool_error_m;
  return c;
}

// Five runs: successes after 1, 1, 2 and 4 attempts, a failure after 12.
std::vector<MissionResult> FiveRuns() {
  std::vector<MissionResult> runs = {Result(true, 1, 20.0), Result(true, 1, 30.0),
                                     Result(true, 2, 40.0), Result(true, 4, 90.0),
                                     Result(false, 12, 0.0)};
  runs[0].closes = {Close(0, true, 0.004), Close(1, true, 0.006)};
  runs[3].closes = {Close(0, false, 0.050), Close(1, true, 0.010)};
  runs[4].closes = {Close(0, false, 0.060)};
  return runs;
}

TEST(MissionStatisticsTest, CountsFirstAttemptAndWithinThreeAttemptSuccesses) {
  const MissionStatistics s = SummarizeMissions(FiveRuns());
  EXPECT_EQ(s.runs, 5);
  EXPECT_EQ(s.successes, 4);
  EXPECT_EQ(s.first_attempt_successes, 2);
  EXPECT_EQ(s.successes_within_3, 3);
  EXPECT_DOUBLE_EQ(s.success_rate(), 0.8);
  EXPECT_DOUBLE_EQ(s.first_attempt_rate(), 0.4);
  EXPECT_DOUBLE_EQ(s.within_3_rate(), 0.6);
}

TEST(MissionStatisticsTest, TheAttemptHistogramHoldsEveryRunAndItsSuccesses) {
  const MissionStatistics s = SummarizeMissions(FiveRuns());
  ASSERT_EQ(s.attempts.size(), 4u);
  EXPECT_EQ(s.attempts.at(1).runs, 2);
  EXPECT_EQ(s.attempts.at(1).successes, 2);
  EXPECT_EQ(s.attempts.at(2).runs, 1);
  EXPECT_EQ(s.attempts.at(4).successes, 1);
  EXPECT_EQ(s.attempts.at(12).runs, 1);
  EXPECT_EQ(s.attempts.at(12).successes, 0);
}

TEST(MissionStatisticsTest, TimeToGraspIsTakenOverTheSuccessesOnly) {
  const MissionStatistics s = SummarizeMissions(FiveRuns());
  // 20, 30, 40, 90 s: nearest rank round(0.5 * 3) = 2 and round(0.9 * 3) = 3.
  EXPECT_DOUBLE_EQ(s.time_to_grasp_median_s, 40.0);
  EXPECT_DOUBLE_EQ(s.time_to_grasp_p90_s, 90.0);
  EXPECT_DOUBLE_EQ(s.time_to_grasp_mean_s, 45.0);
}

TEST(MissionStatisticsTest, ClosesAndTheToolErrorArePooledOverEveryRun) {
  const MissionStatistics s = SummarizeMissions(FiveRuns());
  EXPECT_EQ(s.closes, 5);
  EXPECT_EQ(s.holds, 3);
  // 4, 6, 10, 50, 60 mm.
  EXPECT_DOUBLE_EQ(s.tool_error_median_m, 0.010);
  EXPECT_DOUBLE_EQ(s.tool_error_p90_m, 0.060);
}

TEST(MissionStatisticsTest, ThePoseRmseWeighsEachRunByItsFrames) {
  std::vector<MissionResult> runs = FiveRuns();
  runs[0].pose_rmse_m = 0.003;  // 300 frames
  runs[0].grasp_frames = 300;
  runs[1].pose_rmse_m = 0.009;  // 100 frames
  runs[1].grasp_frames = 100;
  // Without frames (no truth, or never grasping): left out.
  const MissionStatistics s = SummarizeMissions(runs);
  EXPECT_NEAR(s.pose_rmse_m, std::sqrt((300 * 9e-6 + 100 * 81e-6) / 400.0), 1e-12);
}

TEST(MissionStatisticsTest, SafetyCountsAddUpAndTheServoStepIsTheWorstOfAll) {
  std::vector<MissionResult> runs = FiveRuns();
  runs[1].safe_volume_entries = 1;
  runs[2].arm_contacts = 2;
  runs[4].emergency_stops = 1;
  runs[0].servo_step_ms_max = 1.5;
  runs[3].servo_step_ms_max = 3.5;
  runs[3].servo_step_cpu_ms_max = 0.8;
  runs[2].realtime_factor = 1.2;
  runs[3].realtime_factor = 9.0;
  const MissionStatistics s = SummarizeMissions(runs);
  EXPECT_EQ(s.safe_volume_entries, 1);
  EXPECT_EQ(s.arm_contacts, 2);
  EXPECT_EQ(s.emergency_stops, 1);
  EXPECT_DOUBLE_EQ(s.servo_step_ms_max, 3.5);
  EXPECT_DOUBLE_EQ(s.servo_step_cpu_ms_max, 0.8);
  EXPECT_DOUBLE_EQ(s.realtime_factor_min, 1.2);
  EXPECT_DOUBLE_EQ(s.realtime_factor_median, 5.0);
}

TEST(MissionStatisticsTest, FiguresWithoutSamplesAreNanAndNullInJson) {
  const MissionStatistics s = SummarizeMissions({Result(false, 12, 0.0)});
  EXPECT_TRUE(std::isnan(s.time_to_grasp_median_s));
  EXPECT_TRUE(std::isnan(s.tool_error_median_m));
  EXPECT_TRUE(std::isnan(s.pose_rmse_m));
  const nlohmann::json j = MissionStatisticsJson(s);
  EXPECT_TRUE(j["time_to_grasp_s_median"].is_null());
  EXPECT_TRUE(j["tool_error_at_contact_m_p90"].is_null());
  EXPECT_TRUE(j["pose_rmse_while_grasping_m"].is_null());
  EXPECT_EQ(j["first_attempt_success_rate"].get<double>(), 0.0);
  EXPECT_THAT(DescribeMissionStatistics(s), HasSubstr("time to grasp: median n/a"));
}

TEST(MissionStatisticsTest, TheJsonTheTextAndTheReportRowsCarryTheFigures) {
  const MissionStatistics s = SummarizeMissions(FiveRuns());
  const nlohmann::json j = MissionStatisticsJson(s);
  EXPECT_EQ(j["first_attempt_successes"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(j["success_within_3_attempts_rate"].get<double>(), 0.6);
  ASSERT_EQ(j["attempts_histogram"].size(), 4u);
  EXPECT_EQ(j["attempts_histogram"][3]["attempts"].get<int>(), 12);
  EXPECT_EQ(j["attempts_histogram"][3]["runs"].get<int>(), 1);
  EXPECT_EQ(j["gripper_holds"].get<int>(), 3);
  EXPECT_DOUBLE_EQ(j["time_to_grasp_s_p90"].get<double>(), 90.0);
  const std::string text = DescribeMissionStatistics(s);
  EXPECT_THAT(text, HasSubstr("4 of 5 succeeded (80.0 %)"));
  EXPECT_THAT(text, HasSubstr("on the first attempt 2 of 5 (40.0 %)"));
  EXPECT_THAT(text, HasSubstr("within 3 attempts 3 of 5 (60.0 %)"));
  EXPECT_THAT(text, HasSubstr("1: 2 of 2, 2: 1 of 1, 4: 1 of 1, 12: 0 of 1"));
  EXPECT_THAT(text, HasSubstr("median 10.0 mm, 90th percentile 60.0 mm"));
  const ReportRow rows = MissionStatisticsRows(s);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().first, "success rate");
}

TEST(MissionStatisticsTest, ARunsEntryCarriesItsClosesAndFirstAttempt) {
  const std::vector<MissionResult> runs = FiveRuns();
  const nlohmann::json first = MissionRunJson(7, runs[0]);
  EXPECT_EQ(first["seed"].get<int>(), 7);
  EXPECT_TRUE(first["first_attempt_success"].get<bool>());
  EXPECT_EQ(first["gripper_closes"].get<int>(), 2);
  EXPECT_EQ(first["gripper_holds"].get<int>(), 2);
  ASSERT_EQ(first["closes"].size(), 2u);
  EXPECT_EQ(first["closes"][1]["arm"].get<std::string>(), "right");
  EXPECT_DOUBLE_EQ(first["tool_error_at_contact_m_median"].get<double>(), 0.006);
  const nlohmann::json failed = MissionRunJson(8, runs[4]);
  EXPECT_FALSE(failed["first_attempt_success"].get<bool>());
  EXPECT_TRUE(failed["time_to_grasp_s"].is_null());
  const nlohmann::json fourth = MissionRunJson(9, runs[3]);
  EXPECT_FALSE(fourth["first_attempt_success"].get<bool>());
}

}  // namespace
}  // namespace aerograsp
