// A fixture with one output folder per test, named by the test (ctest runs the
// tests in parallel processes, so they must not share one), removed before and
// after the test, and the summary.json a command wrote there.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

namespace aerograsp::testing {

class OutputFolderTest : public ::testing::Test {
 protected:
  /// `prefix` starts the folder's name, e.g. "aerograsp_bench_".
  explicit OutputFolderTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    folder_ = (std::filesystem::temp_directory_path() /
               (prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name()))
                  .string();
    std::filesystem::remove_all(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  nlohmann::json Summary() const {
    std::ifstream in(std::filesystem::path(folder_) / "summary.json");
    return nlohmann::json::parse(in);
  }
  std::string prefix_;
  std::string folder_;
};

}  // namespace aerograsp::testing
