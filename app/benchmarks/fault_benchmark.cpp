#include "app/benchmarks/fault_benchmark.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli_checks.h"
#include "app/report/report_folder.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "app/runtime/mission_record.h"
#include "app/runtime/mission_runner.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "hardware/hardware_config.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kKinds = {"servo_silent",    "servo_slow",        "bus_corrupt",
                                         "link_loss",       "command_rejected",  "camera_frozen",
                                         "camera_no_depth", "object_knocked_off"};

// What each fault is made of. Commands go to the autopilot only at a few
// moments (arm and take-off at the start, the switch to offboard when the
// approach begins at about 3 s, the landing): a refusal is injected in [1, 3] s
// so that the switch to offboard meets it.
constexpr double kRejectFrom_s = 1.0, kRejectTo_s = 3.0;
constexpr double kCorruptProbability = 0.02;   // of each reply byte
constexpr double kSlowBeyondTimeout_s = 0.03;  // a slow servo answers this long after the timeout
// Each mission ends this long after its fault (a stop ends it a second after the stop).
constexpr double kAfterFault_s = 5.0;
constexpr double kAfterKnockOff_s = 15.0;
constexpr double kGoal_s = 0.1;  // safe state within this long of the fault showing

/// One faulty mission's facts.
struct Flight {
  std::string kind;
  std::uint64_t seed = 0;
  double inject_s = 0;
  int servo_id = -1;
  MissionResult result;
  double detectable_s = -1;  // the fault first showed on a device; < 0: never
  double stopped_s = -1;     // the arms' emergency stop; < 0: never
  std::string stop_cause;    // its cause
  bool stopped_for_fault = false;
  double vision_lost_s = -1;  // knocked off: the first "pose lost" after it
  bool log_complete = false;
  std::string log_file;
};

bool CallsForSafeState(const std::string& kind) { return kind != "object_knocked_off"; }

std::vector<int> ServoIds(const HardwareConfig& hw) {
  std::vector<int> ids;
  if (hw.arms.servos_given) {
    for (const auto& side : hw.arms.scs.joints)
      for (const ServoCalibration& c : side) ids.push_back(c.id);
  } else {
    for (int arm : {1, 2})
      for (int j = 1; j <= 4; ++j) ids.push_back(10 * arm + j);  // ScsArmsConfig::Default, 4 DoF
  }
  return ids;
}

/// Sets the fault on the devices (or the world) and returns the servo chosen.
int Inject(const std::string& kind, double t_s, FastRandom* rng, const std::vector<int>& ids,
           HardwareConfig* hw) {
  const int id = ids[rng->Next() % ids.size()];
  if (kind == "servo_silent" || kind == "servo_slow" || kind == "bus_corrupt") {
    SimServoBusConfig& bus = hw->arms.sim_bus;
    bus.faults_from_s = t_s;
    if (kind == "servo_silent") bus.silent_ids = {id};
    if (kind == "servo_slow") {
      bus.slow_ids = {id};
      bus.slow_extra_s = hw->arms.scs.reply_timeout_s + kSlowBeyondTimeout_s;
    }
    if (kind == "bus_corrupt") bus.corrupt_probability = kCorruptProbability;
    return kind == "bus_corrupt" ? -1 : id;
  }
  if (kind == "link_loss" || kind == "command_rejected") {
    hw->autopilot.sim_px4.faults_from_s = t_s;
    hw->autopilot.sim_px4.silent = kind == "link_loss";
    hw->autopilot.sim_px4.reject_commands = kind == "command_rejected";
  } else if (kind == "camera_frozen" || kind == "camera_no_depth") {
    hw->camera.sim.faults_from_s = t_s;
    hw->camera.sim.frozen = kind == "camera_frozen";
    hw->camera.sim.no_depth = kind == "camera_no_depth";
  }
  return -1;
}

/// The log holds the fault once (a device fault line, or the interlock) when
/// the arms stopped for it, and the mission's last line.
bool LogComplete(const std::string& log, const Flight& f) {
  const bool ended = log.find("mission failed:") != std::string::npos ||
                     log.find("mission succeeded") != std::string::npos;
  if (!ended) return false;
  if (!f.stopped_for_fault) return true;
  // Each device fault (device and kind) once: the first line names it.
  const std::string line = "device fault: " + f.stop_cause + "\n";
  std::size_t count = 0;
  for (std::size_t at = log.find(line); at != std::string::npos; at = log.find(line, at + 1))
    ++count;
  return count == 1;
}

Flight Fly(const FaultBenchmarkOptions& options, const std::string& kind, std::uint64_t seed,
           const std::vector<int>& ids, const fs::path& logs) {
  Flight f;
  f.kind = kind;
  f.seed = seed;
  FastRandom rng(seed * 0x9E3779B97F4A7C15ull + 0xFA017);
  f.inject_s = kind == "command_rejected" ? rng.Uniform(kRejectFrom_s, kRejectTo_s)
                                          : rng.Uniform(options.from_s, options.to_s);
  MissionOptions m;
  m.seed = seed;
  m.hardware_path = options.hardware_path;
  m.timeout_s = f.inject_s + (kind == "object_knocked_off" ? kAfterKnockOff_s : kAfterFault_s);
  m.adjust_hardware = [&](HardwareConfig* hw) {
    f.servo_id = Inject(kind, f.inject_s, &rng, ids, hw);
  };
  if (kind == "object_knocked_off") {
    m.adjust_world = [&](WorldConfig* w) { w->object.knocked_off_at_s = f.inject_s; };
  }
  MissionRecord record;
  std::ostringstream log;
  f.result = RunMission(m, &record, &log);
  f.detectable_s = kind == "object_knocked_off" ? f.inject_s : f.result.simulated_fault_s;
  for (const MissionTransition& t : record.transitions) {
    if (f.stopped_s < 0 && t.machine == "arms" && t.to == "emergency stop") {
      f.stopped_s = t.t_s;
      f.stop_cause = t.cause;
    }
    if (f.vision_lost_s < 0 && t.machine == "vision" && t.to == "lost" && t.t_s >= f.inject_s)
      f.vision_lost_s = t.t_s;
  }
  // Stopped for the fault: by a device fault (its log line names it) or the
  // safe-volume interlock, at or after the fault showed.
  const std::string text = log.str();
  f.stopped_for_fault = f.stopped_s >= 0 && f.detectable_s >= 0 &&
                        f.stopped_s + 1e-9 >= f.detectable_s &&
                        (text.find("device fault: " + f.stop_cause) != std::string::npos ||
                         f.stop_cause.find("entered the safe volume") != std::string::npos);
  f.log_complete = LogComplete(text, f);
  f.log_file = fmt::format("{}_{}.log", kind, seed);
  std::ofstream(logs / f.log_file) << text;
  return f;
}

nlohmann::json FlightJson(const Flight& f) {
  const auto opt = [](double v) { return v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
  const bool timed = f.stopped_for_fault;
  return {{"kind", f.kind},
          {"seed", f.seed},
          {"inject_s", f.inject_s},
          {"servo_id", f.servo_id >= 0 ? nlohmann::json(f.servo_id) : nlohmann::json(nullptr)},
          {"detectable_s", opt(f.detectable_s)},
          {"arms_stopped_s", opt(f.stopped_s)},
          {"stop_cause", f.stop_cause},
          {"safe_state_for_fault", f.stopped_for_fault},
          {"latency_s", timed ? nlohmann::json(f.stopped_s - f.detectable_s) : nullptr},
          {"vision_lost_s", opt(f.vision_lost_s)},
          {"safe_volume_entries", f.result.safe_volume_entries},
          {"arm_contacts", f.result.arm_contacts},
          {"device_faults", f.result.device_faults},
          {"failure", f.result.failure},
          {"log_complete", f.log_complete},
          {"log", "logs/" + f.log_file},
          {"wall_time_s", f.result.wall_time_s}};
}

}  // namespace

void AddFaultBenchmarkOptions(CLI::App* cmd, FaultBenchmarkOptions* o) {
  cmd->add_option("--out", o->out_dir, "Report folder: summary.json, logs/")->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--missions", o->missions, "Faulty missions (the fault kinds take turns)")
      ->check(cli::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the first mission (then +1, +2, ...)")
      ->check(cli::Seed())
      ->capture_default_str();
  cmd->add_option("--hardware", o->hardware_path,
                  "Hardware YAML with simulated peers (default data/config/hardware_sim.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--kinds", o->kinds, "Fault kinds to fly (default all)")
      ->check(CLI::IsMember(kKinds));
  cmd->add_option("--from", o->from_s, "Faults injected from this simulated time, s")
      ->check(cli::Range(0.5, 600))
      ->capture_default_str();
  cmd->add_option("--to", o->to_s, "... up to this one, s")
      ->check(cli::Range(0.5, 600))
      ->capture_default_str();
}

void RunFaultBenchmark(const FaultBenchmarkOptions& options_in, std::ostream& out) {
  FaultBenchmarkOptions options = options_in;
  if (options.hardware_path.empty()) options.hardware_path = DataPath("config/hardware_sim.yaml");
  if (options.to_s < options.from_s)
    throw ConfigError(
        fmt::format("--to: {} s is before --from {} s", options.to_s, options.from_s));
  const HardwareConfig hw = HardwareConfig::Load(options.hardware_path);
  if (hw.arms.backend != "sim-bus" || hw.autopilot.backend != "sim-px4" ||
      hw.camera.backend != "sim") {
    throw ConfigError(options.hardware_path +
                      ": the fault benchmark needs arms.backend sim-bus, autopilot.backend "
                      "sim-px4 and camera.backend sim (faults are injected into simulated peers)");
  }
  const std::vector<std::string> kinds = options.kinds.empty() ? kKinds : options.kinds;
  const std::vector<int> ids = ServoIds(hw);
  ReportFolder folder(options.out_dir, options.overwrite);
  const fs::path logs = fs::path(folder.path()) / "logs";
  fs::create_directories(logs);

  out << fmt::format(
      "benchmark faults: {} missions over {} (real SCS and PX4 drivers, simulated peers), "
      "faults from {:.0f} to {:.0f} s\n",
      options.missions, options.hardware_path, options.from_s, options.to_s);
  std::vector<Flight> flights;
  for (int i = 0; i < options.missions; ++i) {
    const std::string& kind = kinds[static_cast<std::size_t>(i) % kinds.size()];
    flights.push_back(Fly(options, kind, options.seed + static_cast<std::uint64_t>(i), ids, logs));
    const Flight& f = flights.back();
    out << fmt::format("  [{:3}/{}] {:<18} seed {:<4} at {:6.2f} s: {}\n", i + 1, options.missions,
                       kind, f.seed, f.inject_s,
                       f.stopped_for_fault ? fmt::format("safe state {:.3f} s after it showed ({})",
                                                         f.stopped_s - f.detectable_s, f.stop_cause)
                       : f.detectable_s < 0 ? "the fault never showed (" + f.result.failure + ")"
                                            : "no safe state for it (" + f.result.failure + ")");
  }

  // Per kind.
  nlohmann::json per_kind = nlohmann::json::object();
  int called = 0, reached = 0, within = 0, entries = 0, contacts = 0, complete = 0;
  std::vector<double> all_latencies;
  out << fmt::format("\n{:<18} {:>4} {:>6} {:>6} {:>7} {:>10} {:>10} {:>7} {:>8} {:>5}\n", "fault",
                     "runs", "shown", "safe", "<0.1 s", "median s", "max s", "entries", "contacts",
                     "logs");
  for (const std::string& kind : kinds) {
    int runs = 0, k_shown = 0, k_safe = 0, k_within = 0, k_entries = 0, k_contacts = 0, k_logs = 0;
    std::vector<double> latencies, lost_after;
    for (const Flight& f : flights) {
      if (f.kind != kind) continue;
      ++runs;
      const bool showed = f.detectable_s >= 0;
      k_shown += showed;
      k_safe += f.stopped_for_fault;
      if (f.stopped_for_fault) {
        const double latency = f.stopped_s - f.detectable_s;
        latencies.push_back(latency);
        k_within += latency <= kGoal_s + 1e-9;
      }
      if (f.vision_lost_s >= 0) lost_after.push_back(f.vision_lost_s - f.inject_s);
      k_entries += f.result.safe_volume_entries;
      k_contacts += f.result.arm_contacts;
      k_logs += f.log_complete;
    }
    if (runs == 0) continue;
    const bool calls = CallsForSafeState(kind);
    if (calls) {
      called += k_shown;
      reached += k_safe;
      within += k_within;
      all_latencies.insert(all_latencies.end(), latencies.begin(), latencies.end());
    }
    entries += k_entries;
    contacts += k_contacts;
    complete += k_logs;
    const double median = latencies.empty() ? -1 : Percentile(latencies, 0.5);
    const double max =
        latencies.empty() ? -1 : *std::max_element(latencies.begin(), latencies.end());
    out << fmt::format("{:<18} {:>4} {:>6} {:>6} {:>7} {:>10} {:>10} {:>7} {:>8} {:>5}\n", kind,
                       runs, k_shown, calls ? std::to_string(k_safe) : "n/a",
                       calls ? std::to_string(k_within) : "n/a",
                       median >= 0 ? fmt::format("{:.3f}", median) : "-",
                       max >= 0 ? fmt::format("{:.3f}", max) : "-", k_entries, k_contacts, k_logs);
    nlohmann::json j = {{"runs", runs},
                        {"fault_showed", k_shown},
                        {"calls_for_safe_state", calls},
                        {"safe_state", k_safe},
                        {"safe_state_within_0_1_s", k_within},
                        {"latency_s_median", median >= 0 ? nlohmann::json(median) : nullptr},
                        {"latency_s_max", max >= 0 ? nlohmann::json(max) : nullptr},
                        {"safe_volume_entries", k_entries},
                        {"arm_contacts", k_contacts},
                        {"logs_complete", k_logs}};
    if (!calls) {
      j["vision_lost_after_s_median"] = lost_after.empty()
                                            ? nlohmann::json(nullptr)
                                            : nlohmann::json(Percentile(lost_after, 0.5));
      j["vision_lost_runs"] = lost_after.size();
    }
    per_kind[kind] = j;
  }
  const double max_latency =
      all_latencies.empty() ? -1 : *std::max_element(all_latencies.begin(), all_latencies.end());
  out << fmt::format(
      "\nsafe state within {:.1f} s of the fault showing: {} of {} faults that call for it "
      "({:.1f} %), {} reached it at all; latency median {:.3f} s, max {:.3f} s\n"
      "safe-volume entries {}, arm contacts {}, logs complete {} of {}\n",
      kGoal_s, within, called, called > 0 ? 100.0 * within / called : 0.0, reached,
      all_latencies.empty() ? 0.0 : Percentile(all_latencies, 0.5), std::max(0.0, max_latency),
      entries, contacts, complete, flights.size());

  nlohmann::json missions = nlohmann::json::array();
  for (const Flight& f : flights) missions.push_back(FlightJson(f));
  const nlohmann::json summary = {
      {"stage", "faults"},
      {"hardware", options.hardware_path},
      {"missions", options.missions},
      {"seed", options.seed},
      {"inject_from_s", options.from_s},
      {"inject_to_s", options.to_s},
      {"goal_latency_s", kGoal_s},
      {"faults_calling_for_safe_state", called},
      {"safe_state", reached},
      {"safe_state_within_goal", within},
      {"safe_state_within_goal_rate", called > 0 ? double(within) / called : 0.0},
      {"latency_s_median", all_latencies.empty() ? nlohmann::json(nullptr)
                                                 : nlohmann::json(Percentile(all_latencies, 0.5))},
      {"latency_s_max", max_latency >= 0 ? nlohmann::json(max_latency) : nullptr},
      {"safe_volume_entries", entries},
      {"arm_contacts", contacts},
      {"logs_complete", complete},
      {"per_kind", per_kind},
      {"runs", missions}};
  WriteSummaryFile(folder.path(), summary.dump(2));
  out << "summary: " << folder.Commit() << "/summary.json\n";
}

}  // namespace aerograsp
