#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>

#include "app/runtime/mission_runner.h"
#include "app/runtime/mission_setup.h"

namespace aerograsp {
namespace {

// The first two simulated seconds: enough to build everything a mission builds.
MissionOptions BriefMission(std::uint64_t seed) {
  MissionOptions m;
  m.seed = seed;
  m.timeout_s = 2.0;
  return m;
}

std::string Log(const MissionOptions& options) {
  std::ostringstream log;
  RunMission(options, nullptr, &log, {});
  return log.str();
}

TEST(MissionSetupTest, ASharedSetupIsBuiltOnceAndFliesTheSameMission) {
  MissionOptions options = BriefMission(5002);
  const std::string own = Log(options);  // the planner and placement of its own
  options.setup = std::make_shared<MissionSetup>();
  const std::string first = Log(options);
  ASSERT_TRUE(options.setup->planner);
  ASSERT_TRUE(options.setup->placement.has_value());
  ASSERT_TRUE(options.setup->tracker_model);
  const GraspPlanner* planner = options.setup->planner.get();
  const ModelCloud* tracker_model = options.setup->tracker_model.get();
  const std::string again = Log(options);
  EXPECT_EQ(options.setup->planner.get(), planner);  // reused, not built again
  EXPECT_EQ(options.setup->tracker_model.get(), tracker_model);
  EXPECT_EQ(first, own);
  EXPECT_EQ(again, own);
}

TEST(MissionSetupTest, AnotherConfigurationBuildsItsOwn) {
  MissionOptions options = BriefMission(5003);
  options.setup = std::make_shared<MissionSetup>();
  Log(options);
  const GraspPlanner* crawler = options.setup->planner.get();
  const std::shared_ptr<const ModelCloud> crawler_model = options.setup->tracker_model;
  const std::string crawler_key = options.setup->key;
  options.object = "pipe";
  Log(options);
  EXPECT_NE(options.setup->planner.get(), crawler);
  EXPECT_NE(options.setup->tracker_model, crawler_model);
  EXPECT_NE(options.setup->key, crawler_key);
  EXPECT_EQ(options.setup->planner->object().name, "pipe");
}

}  // namespace
}  // namespace aerograsp
