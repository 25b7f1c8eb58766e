#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/config.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

#define EXPECT_CONFIG_ERROR(statement, substring)                      \
  try {                                                                \
    statement;                                                         \
    ADD_FAILURE() << "expected ConfigError containing: " << substring; \
  } catch (const ConfigError& e) {                                     \
    EXPECT_THAT(e.what(), HasSubstr(substring));                       \
  }

const char* kText = R"(
speed_m_s: 1.5
count: 3
enabled: true
name: crawler
list: [1, 2, 3.5]
nested:
  deeper:
    value_m: 0.25
  words: [a, b]
)";

TEST(ConfigNodeTest, ReadsTypedValues) {
  const ConfigNode c = ConfigNode::Parse(kText, "test.yaml");
  EXPECT_DOUBLE_EQ(c.GetDouble("speed_m_s"), 1.5);
  EXPECT_EQ(c.GetInt("count"), 3);
  EXPECT_TRUE(c.GetBool("enabled"));
  EXPECT_EQ(c.GetString("name"), "crawler");
  EXPECT_EQ(c.GetDoubles("list"), (std::vector<double>{1, 2, 3.5}));
  EXPECT_DOUBLE_EQ(c.Child("nested").Child("deeper").GetDouble("value_m"), 0.25);
  EXPECT_DOUBLE_EQ(c.GetDouble("absent", 7.0), 7.0);
  EXPECT_EQ(c.GetString("absent", "x"), "x");
}

TEST(ConfigNodeTest, MissingKeyNamesFileAndFullKeyPath) {
  const ConfigNode c = ConfigNode::Parse(kText, "test.yaml");
  EXPECT_CONFIG_ERROR(c.Child("nested").Child("deeper").GetDouble("other_m"),
                      "test.yaml: nested.deeper.other_m: missing required key");
}

TEST(ConfigNodeTest, WrongTypeSaysWhatWasFound) {
  const ConfigNode c = ConfigNode::Parse(kText, "test.yaml");
  EXPECT_CONFIG_ERROR(c.GetDouble("name"), "test.yaml: name: expected a number, got 'crawler'");
  EXPECT_CONFIG_ERROR(c.GetInt("speed_m_s"),
                      "test.yaml: speed_m_s: expected an integer, got '1.5'");
  EXPECT_CONFIG_ERROR(c.GetDouble("list"), "list: expected a number, got a list");
  EXPECT_CONFIG_ERROR(c.Child("name"), "name: expected a map, got a scalar");
  EXPECT_CONFIG_ERROR(c.Child("nested").GetDoubles("words"),
                      "nested.words[0]: expected a number, got 'a'");
}

TEST(ConfigNodeTest, ListSizeIsChecked) {
  const ConfigNode c = ConfigNode::Parse(kText, "test.yaml");
  EXPECT_EQ(c.GetVector3("list"), Eigen::Vector3d(1, 2, 3.5));
  EXPECT_CONFIG_ERROR(c.Child("nested").GetVector3("words"),
                      "test.yaml: nested.words: expected 3 numbers, got 2");
  EXPECT_CONFIG_ERROR(c.GetDoubles("list", 4), "test.yaml: list: expected 4 numbers, got 3");
}

TEST(ConfigNodeTest, UnknownKeysAreRejectedWithTheValidOnes) {
  const ConfigNode c = ConfigNode::Parse("speed_m_s: 1\nsped_m_s: 2\n", "typo.yaml");
  EXPECT_CONFIG_ERROR(c.RequireOnlyKeys({"speed_m_s"}),
                      "typo.yaml: sped_m_s: unknown key (expected one of: speed_m_s)");
}

TEST(ConfigNodeTest, NonFiniteNumbersAreRejected) {
  const ConfigNode c = ConfigNode::Parse("gain: .nan\n", "nan.yaml");
  EXPECT_CONFIG_ERROR(c.GetDouble("gain"), "nan.yaml: gain: expected a finite number");
}

TEST(ConfigNodeTest, DuplicateKeysAreRefusedWithTheirLine) {
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("a: 1\nb:\n  c: 2\n  c: 3\n", "dup.yaml"),
                      "dup.yaml: b.c: line 4: duplicate key (given twice in one map)");
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("a: 1\na: 2\n", "dup.yaml"),
                      "dup.yaml: a: line 2: duplicate key");
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("l:\n  - {x: 1, x: 2}\n", "dup.yaml"),
                      "dup.yaml: l[0].x: line 2: duplicate key");
}

TEST(ConfigNodeTest, AKeyThatIsNotAPlainNameIsRefused) {
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("? [1, 2]\n: 3\n", "key.yaml"),
                      "key.yaml: line 1: a key must be a plain name, got a list");
}

TEST(CheckTest, FiniteNamesTheEntry) {
  EXPECT_CONFIG_ERROR(CheckFinite("f.yaml", "q_rad", {0.1, std::nan(""), 0.3}),
                      "f.yaml: q_rad[1]: nan is not a finite number");
  CheckFinite("f.yaml", "q_rad", {0.1, 0.2});
}

TEST(ConfigNodeTest, SyntaxErrorGivesLineAndColumn) {
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("a: [1, 2\nb: 3\n", "broken.yaml"),
                      "broken.yaml: not valid YAML at line");
}

TEST(ConfigNodeTest, TopLevelMustBeAMap) {
  EXPECT_CONFIG_ERROR(ConfigNode::Parse("- 1\n- 2\n", "list.yaml"),
                      "list.yaml: expected a map of keys at the top level, got a list");
}

TEST(ConfigNodeTest, MissingFileIsNamed) {
  EXPECT_CONFIG_ERROR(ConfigNode::LoadFile("/nonexistent/x.yaml"),
                      "/nonexistent/x.yaml: cannot open file");
}

TEST(ConfigNodeTest, PathsResolveAgainstTheFilesFolder) {
  const auto dir = std::filesystem::temp_directory_path() / "aerograsp_config_test";
  std::filesystem::create_directories(dir / "sub");
  const auto file = dir / "sub" / "c.yaml";
  std::ofstream(file) << "model: ../robots/arm.urdf\nabs: /etc/hosts\n";
  const ConfigNode c = ConfigNode::LoadFile(file.string());
  EXPECT_EQ(c.GetPath("model"), (dir / "robots" / "arm.urdf").string());
  EXPECT_EQ(c.GetPath("abs"), "/etc/hosts");
  std::filesystem::remove_all(dir);
}

TEST(CheckTest, RangeMessagesCarryBoundAndUnit) {
  EXPECT_CONFIG_ERROR(CheckRange("p.yaml", "gripper.max_aperture_m", 0.5, 0.001, 0.3, "m"),
                      "p.yaml: gripper.max_aperture_m: 0.5 m is above the upper bound 0.3 m");
  EXPECT_CONFIG_ERROR(CheckRange("p.yaml", "k", -2, 0, 1, ""),
                      "p.yaml: k: -2 is below the lower bound 0");
  EXPECT_CONFIG_ERROR(CheckPositive("p.yaml", "t_s", 0, "s"), "p.yaml: t_s: 0 s must be positive");
  EXPECT_CONFIG_ERROR(CheckOneOf("p.yaml", "arm_type", "5dof", {"4dof", "6dof"}),
                      "p.yaml: arm_type: '5dof' is not one of: 4dof, 6dof");
  EXPECT_NO_THROW(CheckRange("p.yaml", "k", 0.3, 0.001, 0.3, "m"));
}

}  // namespace
}  // namespace aerograsp
