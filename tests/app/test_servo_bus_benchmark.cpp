#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/benchmarks/servo_bus_benchmark.h"

namespace aerograsp {
namespace {

TEST(ServoBusBenchmarkTest, WritesCycleRateToSummary) {
  ServoBusBenchmarkOptions options;
  options.out_dir = ::testing::TempDir() + "/servo_bus_bench";
  std::filesystem::remove_all(options.out_dir);
  options.cycles = 20;
  std::ostringstream out;
  RunServoBusBenchmark(options, out);
  EXPECT_NE(out.str().find("cycle_hz"), std::string::npos) << out.str();
  std::ifstream file(options.out_dir + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(file);
  EXPECT_EQ(summary["stage"], "servo-bus");
  EXPECT_EQ(summary["servos"], 10);
  EXPECT_GT(summary["cycle_hz"].get<double>(),
            0.0);  // speed is the benchmark's business, not the test's
}

}  // namespace
}  // namespace aerograsp
