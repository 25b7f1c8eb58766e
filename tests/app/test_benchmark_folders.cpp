// Every benchmark writes its report as a transaction (app/report/report_folder.h):
// an earlier report is refused without --overwrite before anything is measured,
// and replaced whole with it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "app/benchmarks/fault_benchmark.h"
#include "app/benchmarks/perception_benchmark.h"
#include "app/benchmarks/render_benchmark.h"
#include "app/benchmarks/servo_benchmark.h"
#include "app/benchmarks/servo_bus_benchmark.h"
#include "core/data_dir.h"
#include "tests/common/earlier_report.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

class BenchmarkFoldersTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("aerograsp_benchmark_folders_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = (root_ / "report").string();
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
  std::string dir_;
  std::ostringstream out_, progress_;
};

TEST_F(BenchmarkFoldersTest, RenderRefusesAnEarlierReportAndReplacesItWithOverwrite) {
  RenderBenchmarkOptions options;
  options.out_dir = dir_;
  options.frames = 1;
  testing::ExpectRefusesAnEarlierReport([&] { RunRenderBenchmark(options, out_); }, dir_);
  options.overwrite = true;
  RunRenderBenchmark(options, out_);
  testing::ExpectReplacedTheEarlierReport(dir_);
}

TEST_F(BenchmarkFoldersTest, ServoBusRefusesAnEarlierReportAndReplacesItWithOverwrite) {
  ServoBusBenchmarkOptions options;
  options.out_dir = dir_;
  options.cycles = 10;
  testing::ExpectRefusesAnEarlierReport([&] { RunServoBusBenchmark(options, out_); }, dir_);
  options.overwrite = true;
  RunServoBusBenchmark(options, out_);
  testing::ExpectReplacedTheEarlierReport(dir_);
}

TEST_F(BenchmarkFoldersTest, ServoRefusesAnEarlierReportAndReplacesItWithOverwrite) {
  ServoBenchmarkOptions options;
  options.out_dir = dir_;
  options.configs = {DataPath("config/platform_4dof.yaml")};
  options.trials = 1;
  options.safety_trials = 0;
  testing::ExpectRefusesAnEarlierReport([&] { RunServoBenchmark(options, out_); }, dir_);
  options.overwrite = true;
  RunServoBenchmark(options, out_);
  testing::ExpectReplacedTheEarlierReport(dir_);
}

TEST_F(BenchmarkFoldersTest, PerceptionAndFaultsRefuseAnEarlierReportBeforeAnyRun) {
  PerceptionBenchmarkOptions perception;
  perception.out_dir = dir_;
  testing::ExpectRefusesAnEarlierReport(
      [&] { RunPerceptionBenchmark(perception, out_, progress_); }, dir_);
  FaultBenchmarkOptions faults;
  faults.out_dir = dir_;
  testing::ExpectRefusesAnEarlierReport([&] { RunFaultBenchmark(faults, out_); }, dir_);
}

}  // namespace
}  // namespace aerograsp
