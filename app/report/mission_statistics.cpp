#include "app/report/mission_statistics.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "app/report/statistics.h"

namespace aerograsp {
namespace {

nlohmann::json OrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

/// A non-negative figure, or null when it is negative (the result's "none").
nlohmann::json IfSet(double v) { return v >= 0 ? nlohmann::json(v) : nullptr; }

std::vector<double> ToolErrors(const std::vector<GripperClose>& closes) {
  std::vector<double> errors;
  for (const GripperClose& c : closes) errors.push_back(c.tool_error_m);
  return errors;
}

int Holds(const std::vector<GripperClose>& closes) {
  return static_cast<int>(
      std::count_if(closes.begin(), closes.end(), [](const GripperClose& c) { return c.holds; }));
}

std::string Millimetres(double m) {
  return std::isfinite(m) ? fmt::format("{:.1f} mm", 1e3 * m) : "n/a";
}

std::string Seconds(double s) { return std::isfinite(s) ? fmt::format("{:.1f} s", s) : "n/a"; }

std::string Share(int count, int of) {
  return fmt::format("{} of {} ({:.1f} %)", count, of, of > 0 ? 100.0 * count / of : 0.0);
}

std::string AttemptsText(const MissionStatistics& s) {
  std::string text;
  for (const auto& [attempts, count] : s.attempts) {
    text += fmt::format("{}{}: {} of {}", text.empty() ? "" : ", ", attempts, count.successes,
                        count.runs);
  }
  return text.empty() ? "none" : text;
}

}  // namespace

MissionStatistics SummarizeMissions(const std::vector<MissionResult>& runs) {
  MissionStatistics s;
  s.runs = static_cast<int>(runs.size());
  std::vector<double> times_s, errors_m, factors, cpu_factors, step_ms, step_cpu_ms;
  double sq_pose = 0.0;
  int pose_frames = 0;
  for (const MissionResult& r : runs) {
    AttemptCount& count = s.attempts[r.attempts];
    ++count.runs;
    if (r.success) {
      ++s.successes;
      ++count.successes;
      s.first_attempt_successes += r.attempts == 1;
      s.successes_within_3 += r.attempts <= 3;
      times_s.push_back(r.time_to_grasp_s);
    }
    s.closes += static_cast<int>(r.closes.size());
    s.holds += Holds(r.closes);
    const std::vector<double> errors = ToolErrors(r.closes);
    errors_m.insert(errors_m.end(), errors.begin(), errors.end());
    if (r.pose_rmse_m >= 0 && r.grasp_frames > 0) {
      sq_pose += r.pose_rmse_m * r.pose_rmse_m * r.grasp_frames;
      pose_frames += r.grasp_frames;
    }
    s.servo_step_ms_max = std::max(s.servo_step_ms_max, r.servo_step_ms_max);
    s.servo_step_cpu_ms_max = std::max(s.servo_step_cpu_ms_max, r.servo_step_cpu_ms_max);
    factors.push_back(r.realtime_factor);
    cpu_factors.push_back(r.realtime_factor_cpu);
    s.safe_volume_entries += r.safe_volume_entries;
    s.arm_contacts += r.arm_contacts;
    s.emergency_stops += r.emergency_stops;
    s.runs_with_switch += r.grasp_switches > 0;
    s.successes_after_switch += r.success && r.grasp_switches > 0;
  }
  s.time_to_grasp_median_s = Percentile(times_s, 0.5, NAN);
  s.time_to_grasp_p90_s = Percentile(times_s, 0.9, NAN);
  if (!times_s.empty()) {
    double sum = 0.0;
    for (double t : times_s) sum += t;
    s.time_to_grasp_mean_s = sum / times_s.size();
  }
  s.tool_error_median_m = Percentile(errors_m, 0.5, NAN);
  s.tool_error_p90_m = Percentile(errors_m, 0.9, NAN);
  if (pose_frames > 0) s.pose_rmse_m = std::sqrt(sq_pose / pose_frames);
  s.realtime_factor_min = Percentile(factors, 0.0);
  s.realtime_factor_median = Percentile(factors, 0.5);
  s.realtime_factor_cpu_min = Percentile(cpu_factors, 0.0);
  s.realtime_factor_cpu_median = Percentile(cpu_factors, 0.5);
  return s;
}

nlohmann::json MissionRunJson(std::uint64_t seed, const MissionResult& r) {
  nlohmann::json j;
  j["seed"] = seed;
  j["success"] = r.success;
  j["failure"] = r.failure;
  j["first_attempt_success"] = r.success && r.attempts == 1;
  j["time_to_grasp_s"] = IfSet(r.time_to_grasp_s);
  j["pose_rmse_m"] = IfSet(r.pose_rmse_m);
  j["rotation_rmse_deg"] = IfSet(r.rotation_rmse_deg);
  j["grasp_frames"] = r.grasp_frames;
  j["grasp_switches"] = r.grasp_switches;
  j["attempts"] = r.attempts;
  j["gripper_closes"] = r.closes.size();
  j["gripper_holds"] = Holds(r.closes);
  const std::vector<double> errors = ToolErrors(r.closes);
  j["tool_error_at_contact_m_median"] = OrNull(Percentile(errors, 0.5, NAN));
  j["tool_error_at_contact_m_p90"] = OrNull(Percentile(errors, 0.9, NAN));
  nlohmann::json closes = nlohmann::json::array();
  for (const GripperClose& c : r.closes) {
    closes.push_back({{"t_s", c.t_s},
                      {"arm", c.arm == 0 ? "left" : "right"},
                      {"holds", c.holds},
                      {"tool_error_m", c.tool_error_m}});
  }
  j["closes"] = closes;
  j["safe_volume_entries"] = r.safe_volume_entries;
  j["arm_contacts"] = r.arm_contacts;
  j["emergency_stops"] = r.emergency_stops;
  j["device_faults"] = r.device_faults;
  j["servo_step_ms_max"] = r.servo_step_ms_max;
  j["servo_step_cpu_ms_max"] = r.servo_step_cpu_ms_max;
  j["realtime_factor"] = r.realtime_factor;
  j["realtime_factor_cpu"] = r.realtime_factor_cpu;
  j["sim_time_s"] = r.sim_time_s;
  j["wall_time_s"] = r.wall_time_s;
  j["cpu_time_s"] = r.cpu_time_s;
  j["frames"] = r.frames;
  j["global_registrations"] = r.global_registrations;
  j["perception_ms_median"] = r.perception_ms_median;
  j["render_ms_median"] = r.render_ms_median;
  return j;
}

nlohmann::json MissionStatisticsJson(const MissionStatistics& s) {
  nlohmann::json j;
  j["successes"] = s.successes;
  j["success_rate"] = s.success_rate();
  j["first_attempt_successes"] = s.first_attempt_successes;
  j["first_attempt_success_rate"] = s.first_attempt_rate();
  j["successes_within_3_attempts"] = s.successes_within_3;
  j["success_within_3_attempts_rate"] = s.within_3_rate();
  nlohmann::json attempts = nlohmann::json::array();
  for (const auto& [n, count] : s.attempts) {
    attempts.push_back({{"attempts", n}, {"runs", count.runs}, {"successes", count.successes}});
  }
  j["attempts_histogram"] = attempts;
  j["time_to_grasp_s_median"] = OrNull(s.time_to_grasp_median_s);
  j["time_to_grasp_s_p90"] = OrNull(s.time_to_grasp_p90_s);
  j["time_to_grasp_s_mean"] = OrNull(s.time_to_grasp_mean_s);
  j["gripper_closes"] = s.closes;
  j["gripper_holds"] = s.holds;
  j["tool_error_at_contact_m_median"] = OrNull(s.tool_error_median_m);
  j["tool_error_at_contact_m_p90"] = OrNull(s.tool_error_p90_m);
  j["pose_rmse_while_grasping_m"] = OrNull(s.pose_rmse_m);
  j["servo_step_ms_max"] = s.servo_step_ms_max;
  j["servo_step_cpu_ms_max"] = s.servo_step_cpu_ms_max;
  j["realtime_factor_min"] = s.realtime_factor_min;
  j["realtime_factor_median"] = s.realtime_factor_median;
  j["realtime_factor_cpu_min"] = s.realtime_factor_cpu_min;
  j["realtime_factor_cpu_median"] = s.realtime_factor_cpu_median;
  j["safe_volume_entries"] = s.safe_volume_entries;
  j["arm_contacts"] = s.arm_contacts;
  j["emergency_stops"] = s.emergency_stops;
  j["runs_with_switch"] = s.runs_with_switch;
  j["successes_after_switch"] = s.successes_after_switch;
  return j;
}

std::string DescribeMissionStatistics(const MissionStatistics& s) {
  std::string text = fmt::format(
      "missions: {} of {} succeeded ({:.1f} %); on the first attempt {}, within 3 attempts {}\n",
      s.successes, s.runs, 100.0 * s.success_rate(), Share(s.first_attempt_successes, s.runs),
      Share(s.successes_within_3, s.runs));
  text += fmt::format("  attempts (succeeded of runs): {}\n", AttemptsText(s));
  text += fmt::format("  time to grasp: median {}, 90th percentile {}\n",
                      Seconds(s.time_to_grasp_median_s), Seconds(s.time_to_grasp_p90_s));
  text += fmt::format(
      "  gripper closes {}, {} held; the tool to the true grasp at contact: median {}, 90th "
      "percentile {}\n",
      s.closes, s.holds, Millimetres(s.tool_error_median_m), Millimetres(s.tool_error_p90_m));
  text += fmt::format("  object estimate while grasping: {} RMSE\n", Millimetres(s.pose_rmse_m));
  text += fmt::format(
      "  worst servo step {:.2f} ms ({:.2f} ms thread CPU); {:.2f}x real time median ({:.2f}x "
      "the slowest), on CPU time {:.2f}x ({:.2f}x)\n",
      s.servo_step_ms_max, s.servo_step_cpu_ms_max, s.realtime_factor_median, s.realtime_factor_min,
      s.realtime_factor_cpu_median, s.realtime_factor_cpu_min);
  text += fmt::format(
      "  safe-volume entries {}, arm contacts {}, emergency stops {}; {} with a grasp switch ({} "
      "of them succeeded)\n",
      s.safe_volume_entries, s.arm_contacts, s.emergency_stops, s.runs_with_switch,
      s.successes_after_switch);
  return text;
}

ReportRow MissionStatisticsRows(const MissionStatistics& s) {
  return {{"success rate",
           fmt::format("{:.1f} % ({} of {})", 100.0 * s.success_rate(), s.successes, s.runs)},
          {"success on the first attempt", Share(s.first_attempt_successes, s.runs)},
          {"success within 3 attempts", Share(s.successes_within_3, s.runs)},
          {"attempts (succeeded of runs)", AttemptsText(s)},
          {"time to grasp",
           fmt::format("median {}, 90th percentile {}", Seconds(s.time_to_grasp_median_s),
                       Seconds(s.time_to_grasp_p90_s))},
          {"gripper closes", fmt::format("{} ({} held)", s.closes, s.holds)},
          {"tool to the true grasp at contact",
           fmt::format("median {}, 90th percentile {}", Millimetres(s.tool_error_median_m),
                       Millimetres(s.tool_error_p90_m))},
          {"object estimate while grasping", Millimetres(s.pose_rmse_m) + " RMSE"},
          {"worst servo step", fmt::format("{:.2f} ms ({:.2f} ms thread CPU)", s.servo_step_ms_max,
                                           s.servo_step_cpu_ms_max)},
          {"real-time factor", fmt::format("{:.2f} median, {:.2f} the slowest",
                                           s.realtime_factor_median, s.realtime_factor_min)},
          {"real-time factor on CPU time",
           fmt::format("{:.2f} median, {:.2f} the slowest", s.realtime_factor_cpu_median,
                       s.realtime_factor_cpu_min)},
          {"safe-volume entries", std::to_string(s.safe_volume_entries)},
          {"arm contacts", std::to_string(s.arm_contacts)},
          {"emergency stops", std::to_string(s.emergency_stops)},
          {"runs with a grasp switch",
           fmt::format("{} ({} of them succeeded)", s.runs_with_switch, s.successes_after_switch)}};
}

ReportRow MissionStatisticsColumns(const MissionStatistics& s) {
  const auto percent = [&](int count) {
    return fmt::format("{:.0f}", s.runs > 0 ? 100.0 * count / s.runs : 0.0);
  };
  const auto seconds = [](double v) { return std::isfinite(v) ? fmt::format("{:.1f}", v) : "-"; };
  const auto mm = [](double v) { return std::isfinite(v) ? fmt::format("{:.1f}", 1e3 * v) : "-"; };
  return {{"runs", std::to_string(s.runs)},
          {"grasped", std::to_string(s.successes)},
          {"1st %", percent(s.first_attempt_successes)},
          {"<=3 %", percent(s.successes_within_3)},
          {"grasp s med/p90",
           fmt::format("{}/{}", seconds(s.time_to_grasp_median_s), seconds(s.time_to_grasp_p90_s))},
          {"closes/holds", fmt::format("{}/{}", s.closes, s.holds)},
          {"tool mm", mm(s.tool_error_median_m)},
          {"RMSE mm", mm(s.pose_rmse_m)},
          {"entries", std::to_string(s.safe_volume_entries)},
          {"contacts", std::to_string(s.arm_contacts)},
          {"servo ms wall/CPU",
           fmt::format("{:.2f}/{:.2f}", s.servo_step_ms_max, s.servo_step_cpu_ms_max)},
          {"RT x min/med",
           fmt::format("{:.1f}/{:.1f}", s.realtime_factor_min, s.realtime_factor_median)},
          {"CPU RT x min/med",
           fmt::format("{:.1f}/{:.1f}", s.realtime_factor_cpu_min, s.realtime_factor_cpu_median)}};
}

ReportRow MissionRunRow(std::uint64_t seed, const MissionResult& r) {
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
          {"on CPU time", fmt::format("{:.2f}", r.realtime_factor_cpu)},
          {"failure", r.failure}};
}

std::string DescribeMissionRun(const MissionResult& r) {
  const MissionStatistics s = SummarizeMissions({r});
  return fmt::format(
      "{}; grasped at {} after {} attempt(s), {} gripper close(s) ({} held), tool to the true "
      "grasp at contact {} median, pose RMSE {}, {} switch(es), {} safe-volume entr{}, {} arm "
      "contact(s), worst servo step {:.2f} ms, {:.2f}x real time ({:.2f}x on CPU time)",
      r.success ? "success" : "FAILED: " + r.failure,
      r.time_to_grasp_s >= 0 ? fmt::format("{:.1f} s", r.time_to_grasp_s) : "never", r.attempts,
      s.closes, s.holds, Millimetres(s.tool_error_median_m),
      r.pose_rmse_m >= 0 ? fmt::format("{:.1f} mm", 1e3 * r.pose_rmse_m) : "n/a", r.grasp_switches,
      r.safe_volume_entries, r.safe_volume_entries == 1 ? "y" : "ies", r.arm_contacts,
      r.servo_step_ms_max, r.realtime_factor, r.realtime_factor_cpu);
}

}  // namespace aerograsp
