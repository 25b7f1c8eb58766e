#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/commands/mission_command.h"
#include "app/exit_codes.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_runner.h"
#include "core/config.h"
#include "detection/perception_config.h"
#include "grasp/planner.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("aerograsp_mission_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  return dir;
}

std::string DataDir() { return AEROGRASP_DATA_DIR; }

// The first 12 simulated seconds: take-off, approach, find the object, start tracking.
MissionOptions ShortMission(std::uint64_t seed) {
  MissionOptions m;
  m.seed = seed;
  m.object = "u_shape";
  m.timeout_s = 12.0;
  return m;
}

TEST(MissionCommandTest, TakesOffFindsTheObjectAndWritesTheReport) {
  const fs::path dir = TempDir("report");
  MissionCommandOptions options;
  options.mission = ShortMission(3);
  options.out_dir = dir.string();
  std::ostringstream out, err;
  EXPECT_EQ(RunMissionCommand(options, out, err), kExitMissionFailed);  // stopped by its limit
  for (const char* file :
       {"index.html", "summary.json", "mission.log", "pose.png", "timeline.png", "joints.png"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  for (const char* key : {"success", "time_to_grasp_s", "pose_rmse_m", "grasp_switches",
                          "safe_volume_entries", "realtime_factor"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_FALSE(summary["success"].get<bool>());  // stopped by the 12 s limit
  EXPECT_EQ(summary["safe_volume_entries"].get<int>(), 0);
  ASSERT_TRUE(summary["pose_rmse_m"].is_number());
  EXPECT_LT(summary["pose_rmse_m"].get<double>(), 0.02);
  const std::string log = out.str();
  // Every machine logged its first transitions with their causes, in order.
  const auto at = [&](const std::string& s) { return log.find(s); };
  ASSERT_NE(at("global  idle -> approaching: start"), std::string::npos) << log;
  ASSERT_NE(at("vehicle idle -> take-off"), std::string::npos);
  ASSERT_NE(at("vehicle take-off -> hover"), std::string::npos);
  ASSERT_NE(at("vision  searching -> found"), std::string::npos);
  ASSERT_NE(at("global  approaching -> grasping"), std::string::npos);
  EXPECT_LT(at("vehicle idle -> take-off"), at("vehicle take-off -> hover"));
  EXPECT_LT(at("vehicle take-off -> hover"), at("global  approaching -> grasping"));
  // The time limit ends in the safe state: arms stopped, vehicle holding.
  EXPECT_NE(at("arms    idle -> emergency stop: the mission took longer than 12 s"),
            std::string::npos)
      << log;
  fs::remove_all(dir);
}

TEST(MissionCommandTest, SeveralRunsWriteTheirTableRateAndSpeedsAndOneLogEach) {
  const fs::path dir = TempDir("runs");
  MissionCommandOptions options;
  options.mission = ShortMission(3);
  options.mission.timeout_s = 4.0;  // taking off: every run fails, quickly
  options.runs = 2;
  options.out_dir = dir.string();
  std::ostringstream out, err;
  EXPECT_EQ(RunMissionCommand(options, out, err), kExitMissionFailed);  // stopped by its limit
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["runs"].size(), 2u);
  EXPECT_EQ(summary["runs"][0]["seed"].get<int>(), 3);
  EXPECT_EQ(summary["runs"][1]["seed"].get<int>(), 4);
  EXPECT_EQ(summary["success_rate"].get<double>(), 0.0);
  const double slowest = summary["realtime_factor_min"].get<double>();
  const double median = summary["realtime_factor_median"].get<double>();
  EXPECT_GT(slowest, 0.0);
  EXPECT_GE(median, slowest);
  EXPECT_TRUE(median == summary["runs"][0]["realtime_factor"].get<double>() ||
              median == summary["runs"][1]["realtime_factor"].get<double>());
  for (const char* log : {"seed_3.log", "seed_4.log"})
    EXPECT_TRUE(fs::exists(dir / "logs" / log)) << log;
  EXPECT_THAT(out.str(), ::testing::HasSubstr("0 of 2 succeeded"));
  EXPECT_THAT(out.str(), ::testing::HasSubstr("x real time median"));
  fs::remove_all(dir);
}

TEST(MissionRunnerTest, TheSameSeedFliesTheSameMission) {
  MissionRecord a, b;
  const MissionResult ra = RunMission(ShortMission(5), &a, nullptr);
  const MissionResult rb = RunMission(ShortMission(5), &b, nullptr);
  ASSERT_EQ(a.transitions.size(), b.transitions.size());
  for (std::size_t i = 0; i < a.transitions.size(); ++i) {
    EXPECT_EQ(a.transitions[i].t_s, b.transitions[i].t_s) << i;
    EXPECT_EQ(a.transitions[i].to, b.transitions[i].to) << i;
  }
  ASSERT_EQ(a.samples.size(), b.samples.size());
  ASSERT_FALSE(a.samples.empty());
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    ASSERT_EQ(a.samples[i].dto_truth_m, b.samples[i].dto_truth_m) << i;
    if (a.samples[i].estimate_valid) {
      ASSERT_EQ(a.samples[i].dto_estimate_m, b.samples[i].dto_estimate_m) << i;
    }
  }
  EXPECT_EQ(ra.pose_rmse_m, rb.pose_rmse_m);
}

TEST(MissionConfigTest, TheShippedConfigLoadsAndBadFieldsAreNamed) {
  const MissionConfig shipped = MissionConfig::Load(DataDir() + "/config/mission_default.yaml");
  EXPECT_DOUBLE_EQ(shipped.servo_rate_hz, 100.0);
  EXPECT_GE(shipped.setpoint_rate_hz, 10.0);
  const fs::path dir = TempDir("config");
  fs::create_directories(dir);
  const auto write = [&](const std::string& text) {
    const fs::path path = dir / "mission.yaml";
    std::ofstream(path) << "world: " << DataDir() << "/config/world_mission.yaml\n" << text;
    return path.string();
  };
  const auto message = [&](const std::string& text) {
    try {
      MissionConfig::Load(write(text));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("servo_rate_hz: 5\n").find("servo_rate_hz"), std::string::npos);
  EXPECT_NE(message("policy:\n  near_tolerance_m: -1\n").find("policy.near_tolerance_m"),
            std::string::npos);
  EXPECT_NE(message("approach_w_m: [1, 2]\n").find("approach_w_m"), std::string::npos);
  EXPECT_NE(message("servo_rate: 100\n").find("servo_rate"), std::string::npos);  // unknown key
  EXPECT_NE(message("policy:\n  max_attempts: 0\n").find("policy.max_attempts"), std::string::npos);
  // Nested settings name their section, key and bound; unknown nested keys are named too.
  const std::string gain = message("servo:\n  gain_per_s: 60\n");
  EXPECT_THAT(gain, ::testing::HasSubstr("mission.yaml: servo.gain_per_s"));
  EXPECT_THAT(gain, ::testing::HasSubstr("50"));
  EXPECT_THAT(message("planner:\n  depth_max_m: 0.5\n"),
              ::testing::HasSubstr("mission.yaml: planner: depth_max_m"));
  EXPECT_THAT(message("grasp_sequence:\n  grasp_tolerance:\n    position_m: 0\n"),
              ::testing::HasSubstr("grasp_sequence.grasp_tolerance.position_m"));
  EXPECT_THAT(message("servo:\n  gain: 15\n"), ::testing::HasSubstr("servo.gain: unknown key"));
  EXPECT_NE(message("perception: no_such_perception.yaml\n").find("no_such_perception.yaml"),
            std::string::npos);
  EXPECT_EQ(shipped.perception, DataDir() + "/config/perception_mission.yaml");
  const PerceptionOptions perception = LoadPerceptionOptions(shipped.perception);
  EXPECT_EQ(perception.track.frames_to_refind, 2);  // the mission's three changes from the defaults
  EXPECT_EQ(perception.cloud.normal_radius_m, 0.015);
  EXPECT_EQ(perception.weak_direction_std_m, 0.02);
  fs::remove_all(dir);
}

// The shipped file is the reference: it reads back from its own YAML, and the
// code's defaults are its values.
TEST(MissionConfigTest, TheShippedFileAndTheDefaultsRoundTripThroughYamlAndAgree) {
  const std::string path = DataDir() + "/config/mission_default.yaml";
  const MissionConfig shipped = MissionConfig::Load(path);
  const fs::path dir = TempDir("round_trip");
  fs::create_directories(dir);
  const auto reload = [&](const MissionConfig& c) {
    const fs::path copy = dir / "mission.yaml";
    std::ofstream(copy) << c.ToYaml();
    return MissionConfig::Load(copy.string());
  };
  EXPECT_EQ(reload(shipped).ToYaml(), shipped.ToYaml());
  MissionConfig defaults;
  defaults.source = "defaults";
  defaults.world = shipped.world;  // the paths as the file resolves them
  defaults.perception = shipped.perception;
  EXPECT_NO_THROW(defaults.Validate());
  EXPECT_EQ(reload(defaults).ToYaml(), defaults.ToYaml());
  EXPECT_EQ(defaults.ToYaml(), shipped.ToYaml());
  fs::remove_all(dir);
}

TEST(MissionRunnerTest, ABadArmTypeOrObjectIsAClearError) {
  MissionOptions m = ShortMission(1);
  m.arm_type = "7dof";
  EXPECT_THROW(RunMission(m, nullptr, nullptr), ConfigError);
  m = ShortMission(1);
  m.object = "no_such_object";
  try {
    RunMission(m, nullptr, nullptr);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_object"), std::string::npos) << e.what();
  }
}

// The simulator against the planner: a planned dual grasp, put on the arms by
// its joints with the vehicle still, holds the object when the grippers close.
TEST(MissionRunnerTest, APlannedGraspSetByItsJointsHoldsTheObjectInTheSimulator) {
  WorldConfig config = WorldConfig::Load(DataDir() + "/config/world_default.yaml");
  config.vehicle.sway_amplitude_m.setZero();
  config.vehicle.tilt_amplitude_rad = 0.0;
  config.vehicle.gust_rate_hz = 0.0;
  config.vehicle.drift_std_m = 0.0;
  config.object.motion = "static";
  // The vehicle placed so that the object sits at the mission's grasp spot.
  const MissionConfig mission = MissionConfig::Load(DataDir() + "/config/mission_default.yaml");
  config.vehicle.start_w_m = World(config, 1).wMo().translation() - mission.grasp_dto_m;
  World world(config, 1);
  const Platform& platform = world.platform();
  world.Step(0.01);
  const Eigen::Isometry3d dMo = world.wMd().inverse() * world.wMo();
  const GraspPlannerConfig planner_config = mission.planner;  // as the mission plans
  const ObjectModel& object = world.object();
  GraspPlanner planner(
      platform, GraspObject{object.name, object.mesh_o, object.mass_kg, object.center_of_mass_o},
      ComputeContactPairs(object.mesh_o, platform.config().gripper, planner_config.contacts),
      planner_config);
  PlanQuery query;
  query.dMo = dMo;
  query.q_left = platform.home(Side::kLeft);
  query.q_right = platform.home(Side::kRight);
  const PlanResult plan = planner.Plan(query);
  ASSERT_FALSE(plan.ranked.empty());
  const DualGrasp& best = plan.ranked.front();
  world.arm(Side::kLeft).SetTarget(best.left.q_grasp);
  world.arm(Side::kRight).SetTarget(best.right.q_grasp);
  world.Step(3.0);
  world.SetGripper(Side::kLeft, GripperCommand::kClose);
  world.SetGripper(Side::kRight, GripperCommand::kClose);
  world.Step(1.5);
  EXPECT_TRUE(world.held_by(Side::kLeft)) << world.gripper(Side::kLeft).aperture_m;
  EXPECT_TRUE(world.held_by(Side::kRight)) << world.gripper(Side::kRight).aperture_m;
}

TEST(MissionRunnerTest, AGripperThatHoldsStaysClosedWhileTheOtherAimsAgain) {
  // Seed 1 (the main job's): the arms switch pairs when the first becomes
  // unreachable; on the second attempt the left gripper takes hold, the right
  // does not; the left keeps the object up while the right arm aims at another
  // pair and takes hold too, and the vehicle flies home with it.
  MissionOptions options;
  options.seed = 1;
  std::ostringstream log;
  MissionRecord record;
  const MissionResult result = RunMission(options, &record, &log);
  EXPECT_THAT(log.str(), ::testing::HasSubstr("gripper holds the object and stays closed"));
  EXPECT_TRUE(result.success) << result.failure << "\n" << log.str();
  EXPECT_GE(result.grasp_switches, 1);
  EXPECT_EQ(result.safe_volume_entries, 0);
}

}  // namespace
}  // namespace aerograsp
