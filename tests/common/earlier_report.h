// An earlier report planted in a command's --out folder: the command must
// refuse it without --overwrite (leaving it as it was) and, with --overwrite,
// replace all of it (app/report/report_folder.h).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "core/config.h"

namespace aerograsp::testing {

/// `dir` holds `signature` (the file every report of the command holds) and a
/// file only the earlier run wrote, both reading "earlier".
inline void PlantEarlierReport(const std::string& dir,
                               const std::string& signature = "summary.json") {
  std::filesystem::create_directories(dir);
  std::ofstream(std::filesystem::path(dir) / signature) << "earlier";
  std::ofstream(std::filesystem::path(dir) / "earlier_only.txt") << "earlier";
}

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Nothing but `dir` itself beside it (no temporary folder left behind).
inline void ExpectNothingBeside(const std::string& dir) {
  const std::filesystem::path d(dir);
  for (const auto& entry : std::filesystem::directory_iterator(d.parent_path())) {
    EXPECT_EQ(entry.path().filename().string().find("." + d.filename().string() + "."),
              std::string::npos)
        << entry.path();
  }
}

/// Plants an earlier report in `dir`, runs `run` (the command without
/// --overwrite) and expects the refusal naming `dir`, the report untouched.
inline void ExpectRefusesAnEarlierReport(const std::function<void()>& run, const std::string& dir,
                                         const std::string& signature = "summary.json") {
  PlantEarlierReport(dir, signature);
  try {
    run();
    ADD_FAILURE() << "the earlier report in " << dir << " was not refused";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": holds an earlier report; --overwrite replaces it");
  }
  const std::filesystem::path d(dir);
  EXPECT_EQ(ReadText(d / signature), "earlier");
  EXPECT_EQ(ReadText(d / "earlier_only.txt"), "earlier");
  ExpectNothingBeside(dir);
}

/// After a run with --overwrite over PlantEarlierReport's folder: none of the
/// earlier run's files is left.
inline void ExpectReplacedTheEarlierReport(const std::string& dir,
                                           const std::string& signature = "summary.json") {
  const std::filesystem::path d(dir);
  EXPECT_FALSE(std::filesystem::exists(d / "earlier_only.txt"));
  EXPECT_TRUE(std::filesystem::exists(d / signature));
  EXPECT_NE(ReadText(d / signature), "earlier");
  ExpectNothingBeside(dir);
}

}  // namespace aerograsp::testing
