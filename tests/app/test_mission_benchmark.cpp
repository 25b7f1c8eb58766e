#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "app/benchmarks/mission_benchmark.h"
#include "app/exit_codes.h"
#include "core/config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("aerograsp_mission_bench_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  return dir;
}

TEST(MissionBenchmarkTest, TwelveCombinationsTheDefaultFirst) {
  const std::vector<MissionBenchmarkConfig> configs = MissionBenchmarkConfigs();
  ASSERT_EQ(configs.size(), 12u);
  EXPECT_EQ(configs.front().name(), "4dof-crawler-crawl");
  std::set<std::string> names;
  for (const MissionBenchmarkConfig& c : configs) names.insert(c.name());
  EXPECT_EQ(names.size(), 12u);
  EXPECT_EQ(names.count("6dof-pipe-static"), 1u);
  EXPECT_EQ(names.count("6dof-u_shape-crawl"), 1u);
}

// Two configurations, the first seconds of flight each: the default one on
// its own number of seeds, the other on --runs, each with its report.
TEST(MissionBenchmarkTest, FliesTheChosenConfigurationsAndWritesTheirReports) {
  const fs::path dir = TempDir("two");
  MissionBenchmarkOptions options;
  options.out_dir = dir.string();
  options.runs_default = 2;
  options.runs = 1;
  options.seed = 11;
  options.timeout_s = 3.0;
  options.configs = {"6dof-pipe-static", "4dof-crawler-crawl"};
  std::ostringstream out, err;
  EXPECT_EQ(RunMissionBenchmark(options, out, err), kExitMissionFailed);  // stopped by the limit
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["missions"].get<int>(), 3);
  const nlohmann::json& configs = summary["configurations"];
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_EQ(configs[0]["configuration"], "4dof-crawler-crawl");  // the benchmark's order
  EXPECT_EQ(configs[0]["runs"].get<int>(), 2);
  EXPECT_EQ(configs[1]["configuration"], "6dof-pipe-static");
  EXPECT_EQ(configs[1]["arm"], "6dof");
  EXPECT_EQ(configs[1]["object"], "pipe");
  EXPECT_EQ(configs[1]["runs"].get<int>(), 1);
  EXPECT_EQ(configs[1]["report"], "6dof-pipe-static/index.html");
  std::ifstream in_config(dir / "6dof-pipe-static" / "summary.json");
  const nlohmann::json runs = nlohmann::json::parse(in_config)["runs"];
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0]["seed"].get<int>(), 11);
  for (const char* key :
       {"first_attempt_success_rate", "success_within_3_attempts_rate", "time_to_grasp_s_median",
        "servo_step_cpu_ms_max", "realtime_factor_min", "safe_volume_entries", "arm_contacts"}) {
    EXPECT_TRUE(configs[1].contains(key)) << key;
  }
  EXPECT_GT(configs[1]["realtime_factor_min"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(dir / "index.html"));
  for (const char* file : {"4dof-crawler-crawl/index.html", "4dof-crawler-crawl/summary.json",
                           "4dof-crawler-crawl/logs/seed_12.log", "6dof-pipe-static/index.html",
                           "6dof-pipe-static/logs/seed_11.log"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  // The table: a header and a row per configuration; a progress line per mission.
  EXPECT_THAT(out.str(), ::testing::HasSubstr("servo ms wall/CPU"));
  EXPECT_THAT(out.str(), ::testing::HasSubstr("\n6dof-pipe-static "));
  EXPECT_THAT(err.str(), ::testing::HasSubstr("[3/3] 6dof-pipe-static 1/1 seed 11"));
  fs::remove_all(dir);
}

TEST(MissionBenchmarkTest, AnUnknownConfigurationIsNamed) {
  MissionBenchmarkOptions options;
  options.out_dir = TempDir("unknown").string();
  options.configs = {"8dof-crawler-crawl"};
  std::ostringstream out, err;
  try {
    RunMissionBenchmark(options, out, err);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("--configs: '8dof-crawler-crawl' is not one of"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("6dof-u_shape-static"));
  }
  EXPECT_FALSE(fs::exists(options.out_dir));
}

}  // namespace
}  // namespace aerograsp
