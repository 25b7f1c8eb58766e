#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/benchmarks/servo_bus_benchmark.h"

namespace aerograsp {
namespace {

/// 20 cycles into a fresh folder `name`: what the benchmark printed and its summary.json.
nlohmann::json RunShortBenchmark(const std::string& name, std::ostringstream* out) {
  ServoBusBenchmarkOptions options;
  options.out_dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(options.out_dir);
  options.cycles = 20;
  RunServoBusBenchmark(options, *out);
  std::ifstream file(options.out_dir + "/summary.json");
  return nlohmann::json::parse(file);
}

TEST(ServoBusBenchmarkTest, WritesCycleRateToSummary) {
  std::ostringstream out;
  const nlohmann::json summary = RunShortBenchmark("servo_bus_bench", &out);
  EXPECT_NE(out.str().find("cycle_hz"), std::string::npos) << out.str();
  EXPECT_EQ(summary["stage"], "servo-bus");
  EXPECT_EQ(summary["servos"], 10);
  EXPECT_GT(summary["cycle_hz"].get<double>(),
            0.0);  // speed is the benchmark's business, not the test's
}

TEST(ServoBusBenchmarkTest, SummaryCountsTheLateRepliesItPrints) {
  std::ostringstream out;
  const nlohmann::json summary = RunShortBenchmark("servo_bus_bench_late", &out);
  // How many come late depends on how long the bus's thread waits for a core:
  // the summary says what the run printed.
  const std::string label = "late replies ";
  const std::size_t at = out.str().find(label);
  ASSERT_NE(at, std::string::npos) << out.str();
  ASSERT_TRUE(summary.contains("late_replies")) << summary.dump(2);
  EXPECT_EQ(summary["late_replies"].get<long>(), std::stol(out.str().substr(at + label.size())));
}

}  // namespace
}  // namespace aerograsp
