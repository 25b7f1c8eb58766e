#include "app/benchmarks/servo_bus_benchmark.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/cli_checks.h"
#include "app/report/report_folder.h"
#include "app/report/summary_file.h"
#include "core/data_dir.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

double Quantile(std::vector<double> values, double q) {
  const std::size_t i = static_cast<std::size_t>(q * (values.size() - 1) + 0.5);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values.end());
  return values[i];
}

}  // namespace

void RunServoBusBenchmark(const ServoBusBenchmarkOptions& options, std::ostream& out) {
  std::optional<ReportFolder> folder;
  if (!options.out_dir.empty()) folder.emplace(options.out_dir, options.overwrite);
  const std::string world_path =
      options.world_config.empty() ? DataPath("config/world_default.yaml") : options.world_config;
  World world(WorldConfig::Load(world_path), 1);
  ScsArmsConfig servos = ScsArmsConfig::Default(world.platform());
  const SimServoBusConfig bus_config;  // wire timing on: 1 Mbaud byte time, servo return delay
  SimServoBus bus(&world, servos, bus_config);
  servos.port = bus.port_path();
  ScsArmsDriver driver(world.platform(), servos, [&world] { return world.now_s(); });

  const double dt_s = 0.01;  // world time per cycle
  std::vector<double> cycle_ms;
  cycle_ms.reserve(static_cast<std::size_t>(options.cycles));
  int failed_reads = 0;
  double busy_s = 0.0;
  for (int i = 0; i < options.cycles; ++i) {
    // Both arms sweep about home so the servos really move.
    for (Side side : kSides) {
      Eigen::VectorXd q = world.platform().home(side);
      q.array() += 0.3 * std::sin(2.0 * M_PI * 0.5 * world.now_s());
      driver.SetJointTargets(side, q);
    }
    const auto t0 = std::chrono::steady_clock::now();
    failed_reads += driver.Cycle().failed_reads;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    busy_s += s;
    cycle_ms.push_back(1e3 * s);
    bus.SyncWithWorld();
    world.Step(dt_s);
  }
  const int servo_count = static_cast<int>(driver.servo_statuses().size());
  // What the wire alone allows: every byte at 10 us, every reply after the return delay.
  std::vector<scs::SyncEntry> entries(static_cast<std::size_t>(servo_count),
                                      {0, std::vector<std::uint8_t>(6)});
  const std::size_t sync_bytes = scs::EncodeSyncWrite(scs::reg::kGoalPosition, 6, entries).size();
  const std::size_t read_bytes = 8 + 8, status_bytes = 8 + 10;
  const std::size_t bytes = sync_bytes + servo_count * read_bytes + status_bytes;
  const double wire_s =
      bytes * bus_config.byte_time_s + (servo_count + 1) * bus_config.return_delay_s;
  // The simulated bus keeps the wire's time on the simulation's clock and
  // never waits for it: the wall time measured is the driver's and the pty's,
  // to which a real wire adds wire_s every cycle.
  const double software_hz = options.cycles / busy_s;
  const double cycle_hz = options.cycles / (busy_s + options.cycles * wire_s);

  out << fmt::format(
      "servo-bus benchmark: {} cycles, {} servos, simulated SCS bus on {} (1 Mbaud wire timing)\n",
      options.cycles, servo_count, bus.port_path());
  out << fmt::format(
      "  cycle: SYNC_WRITE {} B + {} position READs + 1 status READ = {} B on the wire\n",
      sync_bytes, servo_count, bytes);
  out << fmt::format(
      "  cycle_hz {:.1f} with the wire's time (goal >= 100, original controller 30); driver and "
      "pty alone {:.1f}\n",
      cycle_hz, software_hz);
  out << fmt::format(
      "  driver and pty: cycle time median {:.3f} ms, p90 {:.3f} ms, max {:.3f} ms\n",
      Quantile(cycle_ms, 0.5), Quantile(cycle_ms, 0.9),
      *std::max_element(cycle_ms.begin(), cycle_ms.end()));
  const BusCounters counters = driver.counters();
  out << fmt::format(
      "  wire alone: {:.3f} ms ({:.0f} Hz); failed reads {}, late replies {} (skipped)\n",
      1e3 * wire_s, 1.0 / wire_s, failed_reads, counters.late_replies);
  if (!options.out_dir.empty()) {
    const nlohmann::json summary = {
        {"stage", "servo-bus"},
        {"cycles", options.cycles},
        {"servos", servo_count},
        {"cycle_hz", cycle_hz},
        {"software_cycle_hz", software_hz},
        {"cycle_ms_median", Quantile(cycle_ms, 0.5)},
        {"cycle_ms_p90", Quantile(cycle_ms, 0.9)},
        {"cycle_ms_max", *std::max_element(cycle_ms.begin(), cycle_ms.end())},
        {"bytes_per_cycle", bytes},
        {"wire_bound_hz", 1.0 / wire_s},
        {"failed_reads", failed_reads},
        {"bus_timeouts", counters.timeouts},
        {"bus_bad_checksums", counters.bad_checksums},
        {"late_replies", counters.late_replies},
        {"goal_hz", 100.0},
    };
    const std::string path = WriteSummaryFile(folder->path(), summary.dump(2));
    folder->Commit();
    out << "  summary: " << folder->Final(path) << "\n";
  }
}

void AddServoBusBenchmarkOptions(CLI::App* cmd, ServoBusBenchmarkOptions* o) {
  cmd->add_option("--out", o->out_dir, "Folder for summary.json");
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--cycles", o->cycles, "Bus cycles to time")
      ->capture_default_str()
      ->check(cli::Range(10, 1000000));
  cmd->add_option("--world", o->world_config, "World YAML")->check(CLI::ExistingFile);
}

}  // namespace aerograsp
