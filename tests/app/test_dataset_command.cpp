#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands/dataset_command.h"
#include "tests/common/earlier_report.h"
#include "tests/common/output_folder_test.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct Label {
  bool visible = false;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int pixels = 0;
  double coverage = 0;  ///< share of the front-facing model points the depth shows
};

class DatasetCommandTest : public testing::OutputFolderTest {
 protected:
  DatasetCommandTest() : OutputFolderTest("aerograsp_dataset_") {
    options_.object = "pipe";
    options_.count = 6;
    options_.seed = 5;
    options_.overwrite = true;
  }
  std::string Run(const std::string& sub) {
    options_.out_dir = (fs::path(folder_) / sub).string();
    std::ostringstream out, progress;
    RunDatasetCommand(options_, out, progress);
    return out.str();
  }
  std::string Read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::vector<Label> Labels(const std::string& sub) {
    std::istringstream in(Read((fs::path(folder_) / sub / "labels.csv").string()));
    std::string line;
    std::getline(in, line);  // header
    std::vector<Label> labels;
    while (std::getline(in, line)) {
      Label l;
      int index = 0, visible = 0;
      EXPECT_EQ(std::sscanf(line.c_str(), "%d,%d,%lf,%lf,%lf,%lf,%d,%lf", &index, &visible, &l.x0,
                            &l.y0, &l.x1, &l.y1, &l.pixels, &l.coverage),
                8)
          << line;
      l.visible = visible != 0;
      labels.push_back(l);
    }
    return labels;
  }
  DatasetCommandOptions options_;
};

TEST_F(DatasetCommandTest, SameSeedSameImages) {
  EXPECT_THAT(Run("a"), HasSubstr("dataset: 6 images of pipe"));
  Run("b");
  EXPECT_EQ(Read(folder_ + "/a/labels.csv"), Read(folder_ + "/b/labels.csv"));
  EXPECT_EQ(Read(folder_ + "/a/images/000003.png"), Read(folder_ + "/b/images/000003.png"));
}

TEST_F(DatasetCommandTest, OnSupportShowsTheObjectOnItsPipeFromTheVehicle) {
  options_.count = 12;
  Run("floating");
  options_.on_support = 1.0;
  Run("support");
  const std::vector<Label> floating = Labels("floating"), support = Labels("support");
  ASSERT_EQ(support.size(), 12u);
  // Other images than the floating object's (the same seed).
  EXPECT_NE(Read(folder_ + "/floating/labels.csv"), Read(folder_ + "/support/labels.csv"));
  // Seen from 0.3-2.0 m and mostly in view: most images show it, with a box inside the image.
  int visible = 0, covered = 0;
  for (const Label& l : support) {
    EXPECT_GE(l.coverage, 0.0);
    EXPECT_LE(l.coverage, 1.0);
    if (l.pixels == 0)
      EXPECT_EQ(l.coverage, 0.0);  // out of view or hidden: the depth shows none of it
    if (!l.visible) continue;
    ++visible;
    covered += l.coverage >= 0.3;  // replay's test for "visible"
    EXPECT_GE(l.x0, 0.0);
    EXPECT_LE(l.x1, 160.0);
    EXPECT_GE(l.y0, 0.0);
    EXPECT_LE(l.y1, 120.0);
    EXPECT_LT(l.x0, l.x1);
    EXPECT_LT(l.y0, l.y1);
  }
  EXPECT_GE(visible, 7);
  EXPECT_GE(covered, 1);
}

TEST_F(DatasetCommandTest, AnEarlierDatasetIsRefusedAndReplacedWithOverwrite) {
  const std::string dir = folder_ + "/d";
  options_.overwrite = false;
  options_.count = 2;
  testing::ExpectRefusesAnEarlierReport([&] { Run("d"); }, dir, "labels.csv");
  options_.overwrite = true;
  EXPECT_THAT(Run("d"), HasSubstr("dataset: 2 images of pipe in " + dir));
  testing::ExpectReplacedTheEarlierReport(dir, "labels.csv");
  EXPECT_TRUE(fs::exists(dir + "/images/000001.png"));
}

TEST_F(DatasetCommandTest, OnSupportOutOfRangeIsRefused) {
  options_.on_support = 1.5;
  EXPECT_THROW(Run("bad"), std::invalid_argument);
  options_.on_support = -0.1;
  EXPECT_THROW(Run("bad"), std::invalid_argument);
}

}  // namespace
}  // namespace aerograsp
