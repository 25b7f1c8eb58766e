#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "app/commands/robot_command.h"
#include "core/config.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

std::string RunOn(const std::string& config) {
  RobotCommandOptions options;
  options.config_path = std::string(AEROGRASP_DATA_DIR) + "/config/" + config;
  options.reach_samples = 2000;
  std::ostringstream out;
  RunRobotCommand(options, out);
  return out.str();
}

TEST(RobotCommandTest, PrintsTreeCameraAndBothArmsFor4Dof) {
  const std::string out = RunOn("platform_4dof.yaml");
  EXPECT_THAT(out, HasSubstr("arm_left_mount (bl)"));
  EXPECT_THAT(out, HasSubstr("camera_optical (c)"));
  EXPECT_THAT(out, HasSubstr("FOV 55.0 x 42.6 deg"));
  EXPECT_THAT(out, HasSubstr("Left arm: 'arm4'"));
  EXPECT_THAT(out, HasSubstr("Right arm: 'arm4'"));
  EXPECT_THAT(out, HasSubstr("stretched reach 0.443 m"));
  EXPECT_THAT(out, HasSubstr("box 0.900 x 0.900 x 0.290 m"));
}

TEST(RobotCommandTest, PrintsSixJointsFor6Dof) {
  const std::string out = RunOn("platform_6dof.yaml");
  EXPECT_THAT(out, HasSubstr("6 moving joints"));
  EXPECT_THAT(out, HasSubstr("j5"));
}

TEST(RobotCommandTest, SameSeedSameFigures) {
  EXPECT_EQ(RunOn("platform_4dof.yaml"), RunOn("platform_4dof.yaml"));
}

TEST(RobotCommandTest, MissingConfigIsAClearError) {
  RobotCommandOptions options;
  options.config_path = "/nonexistent/platform.yaml";
  std::ostringstream out;
  try {
    RunRobotCommand(options, out);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/platform.yaml: cannot open file"));
  }
}

}  // namespace
}  // namespace aerograsp
