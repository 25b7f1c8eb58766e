#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "app/commands/mission_command.h"
#include "app/exit_codes.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_evaluator.h"
#include "app/runtime/mission_runner.h"
#include "app/runtime/mission_vehicle.h"
#include "core/collision.h"
#include "core/config.h"
#include "detection/perception_config.h"
#include "grasp/planner.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"
#include "servo/ik.h"
#include "tests/common/earlier_report.h"
#include "tests/common/validation_message.h"

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
  for (const char* key :
       {"success", "time_to_grasp_s", "pose_rmse_m", "grasp_switches", "safe_volume_entries",
        "realtime_factor", "first_attempt_success", "attempts", "gripper_closes", "gripper_holds",
        "closes", "tool_error_at_contact_m_median", "arm_contacts", "servo_step_ms_max"}) {
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
  // The time limit ends in the safe state: arms stopped (idle, or moving when
  // a plan came before the limit), vehicle holding.
  EXPECT_THAT(log, ::testing::ContainsRegex(
                       "arms    [a-z]+ -> emergency stop: the mission took longer than 12 s"));
  fs::remove_all(dir);
}

TEST(MissionCommandTest, AnEarlierReportIsRefusedKeptByAFailedStartAndReplacedWithOverwrite) {
  const fs::path dir = TempDir("earlier");
  MissionCommandOptions options;
  options.mission = ShortMission(3);
  options.mission.timeout_s = 2.0;  // on the ground: quick
  options.out_dir = dir.string();
  std::ostringstream out, err;
  testing::ExpectRefusesAnEarlierReport([&] { RunMissionCommand(options, out, err); },
                                        options.out_dir);
  // A mission failing at start leaves the earlier report whole, nothing beside it.
  options.overwrite = true;
  options.mission.object = "no_such_object";
  EXPECT_ANY_THROW(RunMissionCommand(options, out, err));
  EXPECT_EQ(testing::ReadText(dir / "earlier_only.txt"), "earlier");
  EXPECT_EQ(testing::ReadText(dir / "summary.json"), "earlier");
  testing::ExpectNothingBeside(options.out_dir);
  options.mission.object = "u_shape";
  EXPECT_EQ(RunMissionCommand(options, out, err), kExitMissionFailed);  // stopped by its limit
  testing::ExpectReplacedTheEarlierReport(options.out_dir);
  EXPECT_TRUE(fs::exists(dir / "mission.log"));
  fs::remove_all(dir);
}

TEST(MissionCommandTest, SeveralRunsWithABadObjectStopAtOnceKeepingTheEarlierReport) {
  const fs::path dir = TempDir("runs_bad");
  MissionCommandOptions options;
  options.mission = ShortMission(3);
  options.mission.object = "no_such_object";
  options.runs = 30;
  options.out_dir = dir.string();
  options.overwrite = true;
  testing::PlantEarlierReport(options.out_dir, "summary.json");
  std::ostringstream out, err;
  try {
    RunMissionCommand(options, out, err);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("no_such_object"));
  }
  EXPECT_EQ(testing::ReadText(dir / "summary.json"), "earlier");
  EXPECT_FALSE(fs::exists(dir / "logs"));
  testing::ExpectNothingBeside(options.out_dir);
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
  EXPECT_EQ(summary["first_attempt_success_rate"].get<double>(), 0.0);
  EXPECT_TRUE(summary["time_to_grasp_s_median"].is_null());  // no success
  for (const char* key : {"attempts_histogram", "gripper_closes", "tool_error_at_contact_m_p90",
                          "pose_rmse_while_grasping_m", "servo_step_ms_max", "arm_contacts"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
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
              ::testing::HasSubstr("mission.yaml: planner.depth_max_m: 0.5 m is above"));
  EXPECT_THAT(message("grasp_sequence:\n  grasp_tolerance:\n    position_m: 0\n"),
              ::testing::HasSubstr("grasp_sequence.grasp_tolerance.position_m"));
  EXPECT_THAT(message("servo:\n  gain: 15\n"), ::testing::HasSubstr("servo.gain: unknown key"));
  EXPECT_THAT(message("placement:\n  step_m: 0\n"),
              ::testing::HasSubstr("mission.yaml: placement.step_m"));
  EXPECT_THAT(message("vehicle_lag_s: 9\n"), ::testing::HasSubstr("mission.yaml: vehicle_lag_s"));
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
  EXPECT_NO_THROW(defaults.Validate(defaults.source, ""));
  EXPECT_EQ(reload(defaults).ToYaml(), defaults.ToYaml());
  EXPECT_EQ(defaults.ToYaml(), shipped.ToYaml());
  fs::remove_all(dir);
}

// The vehicle follows a crawling object ahead of its filtered position, by
// the filter's and its own lag, and never leaves the geofence.
TEST(MissionVehicleTest, TrackingSetpointLeadsAMovingObjectWithinTheGeofence) {
  MissionConfig config;
  config.yaw_rad = 0.0;
  const Eigen::Vector3d object_w = config.approach_w_m + config.grasp_dto_m;
  const Eigen::Vector3d still = TrackingSetpoint(object_w, Eigen::Vector3d::Zero(), config);
  EXPECT_LT((still - config.approach_w_m).norm(), 1e-12);
  const Eigen::Vector3d v_w(0.0, 0.03, 0.0);
  const Eigen::Vector3d moving = TrackingSetpoint(object_w, v_w, config);
  const double lead_s = config.object_filter_s + config.vehicle_lag_s;
  EXPECT_LT((moving - (config.approach_w_m + lead_s * v_w)).norm(), 1e-12);
  const Eigen::Vector3d far = TrackingSetpoint(object_w, Eigen::Vector3d(0.0, 10.0, 0.0), config);
  EXPECT_NEAR((far - config.approach_w_m).norm(), config.tracking_radius_m, 1e-12);
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

// A world standing still (no sway, tilt, gusts, drift; the object static)
// with the vehicle placed so that the object sits at the mission's grasp spot.
WorldConfig StillWorldAtTheGraspSpot() {
  WorldConfig config = WorldConfig::Load(DataDir() + "/config/world_default.yaml");
  config.vehicle.sway_amplitude_m.setZero();
  config.vehicle.tilt_amplitude_rad = 0.0;
  config.vehicle.gust_rate_hz = 0.0;
  config.vehicle.drift_std_m = 0.0;
  config.object.motion = "static";
  const MissionConfig mission = MissionConfig::Load(DataDir() + "/config/mission_default.yaml");
  config.vehicle.start_w_m = World(config, 1).wMo().translation() - mission.grasp_dto_m;
  return config;
}

// The mission's first-ranked dual grasp for the object where it is now.
DualGrasp PlanInWorld(const World& world) {
  const MissionConfig mission = MissionConfig::Load(DataDir() + "/config/mission_default.yaml");
  const GraspPlannerConfig planner_config = mission.planner;  // as the mission plans
  const ObjectModel& object = world.object();
  const Platform& platform = world.platform();
  GraspPlanner planner(
      platform, GraspObject{object.name, object.mesh_o, object.mass_kg, object.center_of_mass_o},
      ComputeContactPairs(object.mesh_o, platform.config().gripper, planner_config.contacts),
      planner_config);
  PlanQuery query;
  query.dMo = world.wMd().inverse() * world.wMo();
  query.q_left = platform.home(Side::kLeft);
  query.q_right = platform.home(Side::kRight);
  const PlanResult plan = planner.Plan(query);
  if (plan.ranked.empty()) throw std::runtime_error("no dual grasp for the still world");
  return plan.ranked.front();
}

// The simulator against the planner: a planned dual grasp, put on the arms by
// its joints with the vehicle still, holds the object when the grippers close.
TEST(MissionRunnerTest, APlannedGraspSetByItsJointsHoldsTheObjectInTheSimulator) {
  World world(StillWorldAtTheGraspSpot(), 1);
  world.Step(0.01);
  const DualGrasp best = PlanInWorld(world);
  world.arm(Side::kLeft).SetTarget(best.left.q_grasp);
  world.arm(Side::kRight).SetTarget(best.right.q_grasp);
  world.Step(3.0);
  world.SetGripper(Side::kLeft, GripperCommand::kClose);
  world.SetGripper(Side::kRight, GripperCommand::kClose);
  world.Step(1.5);
  EXPECT_TRUE(world.held_by(Side::kLeft)) << world.gripper(Side::kLeft).aperture_m;
  EXPECT_TRUE(world.held_by(Side::kRight)) << world.gripper(Side::kRight).aperture_m;
}

// The left gripper closes on an estimate 20 mm off the truth, the right on the
// truth: the evaluator measures each tool against its grasp on the true object.
TEST(MissionEvaluatorTest, TheToolErrorAtContactIsTakenAgainstTheTrueObject) {
  World world(StillWorldAtTheGraspSpot(), 1);
  world.Step(0.01);
  const DualGrasp best = PlanInWorld(world);
  const Platform& platform = world.platform();
  const PlatformCollision collision(platform);
  std::vector<std::string> lines;
  MissionEvaluator evaluator(world, platform, collision,
                             ObjectSymmetry{{Eigen::Matrix3d::Identity()}},
                             [&](const std::string& line) { lines.push_back(line); });
  const ArmGrasp* grasps[2] = {&best.left, &best.right};
  for (int a = 0; a < 2; ++a) world.arm(kSides[a]).SetTarget(grasps[a]->q_grasp);
  world.Step(3.0);
  const Eigen::Isometry3d dMo_true = world.wMd().inverse() * world.wMo();
  const Eigen::Vector3d offset_d(0.0, 0.02, 0.0);
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    ClosingView view;
    view.dMo_estimate = dMo_true;
    if (a == 0) view.dMo_estimate.translation() += offset_d;
    view.bMg_target = platform.arm(side).ForwardKinematics(grasps[a]->q_grasp);
    view.dMe = platform.dMb(side) * view.bMg_target;
    evaluator.Closing(a, view);
    world.SetGripper(side, GripperCommand::kClose);
  }
  world.Step(1.5);
  evaluator.Closed(0);
  evaluator.Closed(1);
  ASSERT_EQ(evaluator.closes().size(), 2u);
  EXPECT_EQ(evaluator.closes()[0].arm, 0);
  EXPECT_TRUE(evaluator.closes()[1].holds);
  EXPECT_NEAR(evaluator.closes()[0].tool_error_m, 0.02, 0.002);
  EXPECT_LT(evaluator.closes()[1].tool_error_m, 0.002);
  EXPECT_THAT(lines.back(), ::testing::HasSubstr("mm from its grasp"));
}

TEST(MissionEvaluatorTest, ArmsComingIntoContactCountOncePerContact) {
  World world(StillWorldAtTheGraspSpot(), 1);
  const Platform& platform = world.platform();
  const PlatformCollision collision(platform);
  MissionEvaluator evaluator(world, platform, collision,
                             ObjectSymmetry{{Eigen::Matrix3d::Identity()}},
                             [](const std::string&) {});
  evaluator.Step();
  EXPECT_EQ(evaluator.arm_contacts(), 0);  // at home
  std::mt19937 rng(3);
  Eigen::VectorXd q[2];
  do {
    q[0] = DrawJointsWithinLimits(platform.arm(Side::kLeft), &rng);
    q[1] = DrawJointsWithinLimits(platform.arm(Side::kRight), &rng);
  } while (!collision.ArmsCollide(q[0], q[1], 0.0));
  world.arm(Side::kLeft).SetTarget(q[0]);
  world.arm(Side::kRight).SetTarget(q[1]);
  world.Step(5.0);
  ASSERT_TRUE(collision.ArmsCollide(world.arm(Side::kLeft).q_true_rad(),
                                    world.arm(Side::kRight).q_true_rad(), 0.0));
  evaluator.Step();
  evaluator.Step();  // still touching: the same contact
  EXPECT_EQ(evaluator.arm_contacts(), 1);
}

TEST(MissionRunnerTest, AGripperThatHoldsStaysClosedWhileTheOtherAimsAgain) {
  // Seed 5703: on the first attempt the left gripper takes hold and the right
  // closes empty; the holder keeps the object up while the right arm aims at
  // other pairs, and the mission grasps and flies home in the end.
  MissionOptions options;
  options.seed = 5703;
  std::ostringstream log;
  MissionRecord record;
  const MissionResult result = RunMission(options, &record, &log);
  EXPECT_THAT(log.str(), ::testing::HasSubstr("gripper holds the object and stays closed"));
  EXPECT_TRUE(result.success) << result.failure << "\n" << log.str();
  EXPECT_EQ(result.safe_volume_entries, 0);
  EXPECT_EQ(result.arm_contacts, 0);
  // The evaluator kept every close: both grippers ended up holding.
  const auto holds = std::count_if(result.closes.begin(), result.closes.end(),
                                   [](const GripperClose& c) { return c.holds; });
  EXPECT_GE(holds, 2);
  EXPECT_GT(result.servo_step_cpu_ms_max, 0.0);
}

TEST(MissionConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  const MissionConfig shipped = MissionConfig::Load(DataDir() + "/config/mission_default.yaml");
  MissionConfig c = shipped;
  c.takeoff_altitude_m = 30.0;
  EXPECT_THAT(
      testing::ValidationMessage(c, "m.yaml", ""),
      ::testing::HasSubstr("m.yaml: takeoff_altitude_m: 30 m is above the upper bound 20 m"));
  EXPECT_THAT(testing::ValidationMessage(c, "m.yaml", "mission."),
              ::testing::HasSubstr(
                  "m.yaml: mission.takeoff_altitude_m: 30 m is above the upper bound 20 m"));
  c = shipped;
  c.planner.depth_max_m = 0.35;
  EXPECT_THAT(testing::ValidationMessage(c, "m.yaml", "mission."),
              ::testing::HasSubstr(
                  "m.yaml: mission.planner.depth_max_m: 0.35 m is above the upper bound 0.3 m"));
  c = shipped;
  c.servo.gain_per_s = 60.0;
  EXPECT_THAT(testing::ValidationMessage(c, "m.yaml", "mission."),
              ::testing::HasSubstr(
                  "m.yaml: mission.servo.gain_per_s: 60 1/s is above the upper bound 50 1/s"));
}

}  // namespace
}  // namespace aerograsp
