// Report folders as transactions (app/report/report_folder.h): an earlier
// report stays whole until the new one is committed, is refused without
// --overwrite, and a run that throws leaves nothing behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "app/report/report_folder.h"
#include "core/config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

class ReportFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("aerograsp_report_folder_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = root_ / "report";
  }
  void TearDown() override { fs::remove_all(root_); }
  static void Write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }
  static std::string Read(const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  /// Entries of root_ (the report and anything left beside it).
  std::size_t Entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(root_), {}));
  }
  fs::path root_, dir_;
};

TEST_F(ReportFolderTest, WritesAsideAndMovesIntoPlaceAtCommit) {
  ReportFolder folder(dir_.string(), false);
  Write(fs::path(folder.path()) / "summary.json", "{}");
  EXPECT_FALSE(fs::exists(dir_));  // nothing under the report's name before the commit
  EXPECT_EQ(folder.Commit(), dir_.string());
  EXPECT_EQ(Read(dir_ / "summary.json"), "{}");
  EXPECT_EQ(Entries(), 1u);
}

TEST_F(ReportFolderTest, AnEarlierReportIsRefusedWithoutOverwrite) {
  fs::create_directories(dir_);
  Write(dir_ / "summary.json", "old");
  try {
    ReportFolder folder(dir_.string(), false);
    FAIL() << "an earlier report was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              dir_.string() + ": holds an earlier report; --overwrite replaces it");
  }
  EXPECT_EQ(Read(dir_ / "summary.json"), "old");
  EXPECT_EQ(Entries(), 1u);
}

TEST_F(ReportFolderTest, OverwriteReplacesTheWholeEarlierReportAtCommit) {
  fs::create_directories(dir_);
  Write(dir_ / "summary.json", "old");
  Write(dir_ / "poses.csv", "old rows");
  ReportFolder folder(dir_.string(), true);
  Write(fs::path(folder.path()) / "summary.json", "new");
  EXPECT_EQ(Read(dir_ / "summary.json"), "old");  // intact until the commit
  folder.Commit();
  EXPECT_EQ(Read(dir_ / "summary.json"), "new");
  EXPECT_FALSE(fs::exists(dir_ / "poses.csv"));  // no file of the earlier run beside the new ones
  EXPECT_EQ(Entries(), 1u);
}

TEST_F(ReportFolderTest, ARunThatThrowsLeavesTheEarlierReportAndNothingElse) {
  fs::create_directories(dir_);
  Write(dir_ / "summary.json", "old");
  try {
    ReportFolder folder(dir_.string(), true);
    Write(fs::path(folder.path()) / "poses.csv", "");
    throw std::runtime_error("the sequence ended");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(Read(dir_ / "summary.json"), "old");
  EXPECT_FALSE(fs::exists(dir_ / "poses.csv"));
  EXPECT_EQ(Entries(), 1u);
}

TEST_F(ReportFolderTest, AnEmptyFolderIsUsedAndAFileIsRefused) {
  fs::create_directories(dir_);
  {
    ReportFolder folder(dir_.string(), false);
    folder.Commit();
  }
  EXPECT_TRUE(fs::is_directory(dir_));
  const fs::path file = root_ / "notes.txt";
  Write(file, "mine");
  EXPECT_THROW(ReportFolder(file.string(), true), ConfigError);
  EXPECT_EQ(Read(file), "mine");
}

TEST_F(ReportFolderTest, AFolderOfOtherFilesIsNeverReplacedEvenWithOverwrite) {
  fs::create_directories(dir_);
  Write(dir_ / "thesis.tex", "mine");
  try {
    ReportFolder folder(dir_.string(), true);
    FAIL() << "a folder without a report was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), dir_.string() +
                                         ": is not empty and holds no report (no summary.json); "
                                         "choose another folder");
  }
  EXPECT_EQ(Read(dir_ / "thesis.tex"), "mine");
  EXPECT_EQ(Entries(), 1u);
}

TEST_F(ReportFolderTest, NamesWrittenFilesAsTheyWillBeAfterTheCommit) {
  ReportFolder folder(dir_.string() + "/", false, "sequence.yaml");
  EXPECT_EQ(folder.final_path(), dir_.string());
  EXPECT_EQ(folder.Final((fs::path(folder.path()) / "logs" / "a.log").string()),
            (dir_ / "logs" / "a.log").string());
  EXPECT_EQ(folder.Final("/elsewhere/b.log"), "/elsewhere/b.log");
}

TEST_F(ReportFolderTest, NamesTheFolderAsItWillBeWhereverAMessageMentionsIt) {
  ReportFolder folder(dir_.string(), false);
  const std::string work = folder.path();
  EXPECT_EQ(folder.Final("kept in " + work + "/samples.yaml (solve them with `--resolve " + work +
                         "`); see " + work + "."),
            "kept in " + dir_.string() + "/samples.yaml (solve them with `--resolve " +
                dir_.string() + "`); see " + dir_.string() + ".");
  EXPECT_EQ(folder.Final(work + "7/a " + work + ".old/b"), work + "7/a " + work + ".old/b");
}

}  // namespace
}  // namespace aerograsp
