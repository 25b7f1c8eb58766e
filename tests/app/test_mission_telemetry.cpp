#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <sstream>

#include "app/commands/mission_command.h"
#include "app/commands/telemetry_options.h"
#include "app/exit_codes.h"
#include "app/runtime/mission_runner.h"
#include "telemetry/telemetry.h"
#include "tests/common/joint_travel.h"

namespace aerograsp {
namespace {

using aerograsp::testing::JointTravel;
using ::testing::HasSubstr;

/// Keeps what the mission sends, to look at after it.
class RecordingSink final : public TelemetrySink {
 public:
  struct Tf {
    double t_s;
    TelemetryTransform transform;
  };
  std::vector<std::string> calls;  // call names in order
  std::vector<Tf> static_tf, moving_tf;
  std::vector<TelemetryArms> arms;
  std::vector<TelemetryObjectPose> poses;
  std::vector<TelemetryTransition> transitions;
  std::vector<TelemetryGraspPair> pairs;
  std::vector<std::string> log;
  int images = 0;
  bool closed = false;

  void StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) override {
    calls.push_back("static");
    for (const auto& t : transforms) static_tf.push_back({t_s, t});
  }
  void Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) override {
    calls.push_back("tf");
    for (const auto& t : transforms) moving_tf.push_back({t_s, t});
  }
  void ObjectPose(const TelemetryObjectPose& pose) override { poses.push_back(pose); }
  void Arms(const TelemetryArms& a) override { arms.push_back(a); }
  void Transition(const TelemetryTransition& t) override { transitions.push_back(t); }
  void GraspPair(const TelemetryGraspPair& p) override { pairs.push_back(p); }
  void Image(const TelemetryImage& image) override {
    images += image.color != nullptr && !image.color->empty();
  }
  void Log(double, TelemetryLevel, const std::string&, const std::string& line) override {
    log.push_back(line);
  }
  void Close() override { closed = true; }
};

/// An emergency-stop button pressed at a mission time.
class ButtonAt final : public EmergencyStopSource {
 public:
  explicit ButtonAt(double t_s) : t_s_(t_s) {}
  EmergencyStopPoll Poll(double t_s) override {
    EmergencyStopPoll poll;
    if (!polled_) poll.notes.push_back("test button: armed");
    polled_ = true;
    if (t_s >= t_s_) {
      if (first_stop_s_ < 0) first_stop_s_ = t_s;
      poll.stop = true;
      poll.source = "test button";
      poll.reason = "pressed";
    }
    return poll;
  }
  double first_stop_s() const { return first_stop_s_; }

 private:
  double t_s_;
  bool polled_ = false;
  double first_stop_s_ = -1.0;
};

// Seed 1 with the u_shape: the arms servo to their pre-catch poses from about
// 12.8 s to 18 s of mission time; the button is pressed at 13.5 s.
MissionOptions ServoingMission() {
  MissionOptions m;
  m.seed = 1;
  m.object = "u_shape";
  m.timeout_s = 25.0;
  return m;
}

class MissionTelemetryTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sink_ = new RecordingSink;
    button_ = new ButtonAt(13.5);
    MissionLinks links;
    links.telemetry = sink_;
    links.emergency_stop = button_;
    result_ = RunMission(ServoingMission(), nullptr, &log_, links);
  }
  static void TearDownTestSuite() {
    delete sink_;
    delete button_;
  }
  static RecordingSink* sink_;
  static ButtonAt* button_;
  static std::ostringstream log_;
  static MissionResult result_;
};
RecordingSink* MissionTelemetryTest::sink_ = nullptr;
ButtonAt* MissionTelemetryTest::button_ = nullptr;
std::ostringstream MissionTelemetryTest::log_;
MissionResult MissionTelemetryTest::result_;

TEST_F(MissionTelemetryTest, OutsideStopIsTheMissionsEmergencyWithItsSource) {
  EXPECT_FALSE(result_.success);
  EXPECT_EQ(result_.emergency_stops, 1);
  EXPECT_THAT(result_.failure, HasSubstr("emergency stop from test button: pressed"));
  EXPECT_THAT(log_.str(), HasSubstr("test button: armed"));
  EXPECT_THAT(log_.str(), HasSubstr("emergency stop requested by test button"));
  // The arms' machine stopped in the cycle that polled the request.
  bool stopped = false;
  for (const TelemetryTransition& t : sink_->transitions) {
    if (t.machine == "arms" && t.to == "emergency stop") {
      EXPECT_DOUBLE_EQ(t.t_s, button_->first_stop_s());
      EXPECT_THAT(t.cause, HasSubstr("test button"));
      stopped = true;
    }
  }
  EXPECT_TRUE(stopped) << log_.str();
  const double t_stop = button_->first_stop_s();
  ASSERT_GT(t_stop, 0.0);
  // Servoing before the stop, still once the stop's cycle has passed.
  EXPECT_GT(JointTravel(sink_->arms, t_stop - 1.0, t_stop), 0.02);
  EXPECT_LT(JointTravel(sink_->arms, t_stop + 0.02, t_stop + 1.0), 2e-3);
  // From the stop's own cycle: the driver was told to stop, so the arms hold
  // where they were measured, not one servo step on (0.023 rad without it).
  EXPECT_LT(JointTravel(sink_->arms, t_stop, t_stop + 1.0), 1e-4);
}

TEST_F(MissionTelemetryTest, TransformsStaticFirstThenBodyToolsAndObjectEachCycle) {
  ASSERT_FALSE(sink_->calls.empty());
  EXPECT_EQ(sink_->calls.front(), "static");
  std::map<std::string, std::string> parent_of;
  for (const auto& t : sink_->static_tf) parent_of[t.transform.child] = t.transform.parent;
  EXPECT_EQ(parent_of["world"], "map");
  EXPECT_EQ(parent_of["camera_optical"], "body");
  EXPECT_EQ(parent_of["arm_left_mount"], "body");
  EXPECT_EQ(parent_of["arm_right_mount"], "body");
  std::map<std::string, int> count;
  for (const auto& t : sink_->moving_tf) ++count[t.transform.parent + "->" + t.transform.child];
  EXPECT_GT(count["world->body"], 1000);  // every 10 ms cycle of about 14.5 s
  EXPECT_EQ(count["arm_left_mount->arm_left_tool"], count["world->body"]);
  EXPECT_EQ(count["arm_right_mount->arm_right_tool"], count["world->body"]);
  EXPECT_GT(count["world->object"], 100);
  for (std::size_t k = 1; k < sink_->moving_tf.size(); ++k)
    ASSERT_GE(sink_->moving_tf[k].t_s, sink_->moving_tf[k - 1].t_s);
  ASSERT_FALSE(sink_->arms.empty());
  const TelemetryArms& a = sink_->arms.back();
  EXPECT_EQ(a.arms[0].arm, "left");
  EXPECT_EQ(a.arms[1].arm, "right");
  EXPECT_THAT(a.arms[0].joint_names, ::testing::ElementsAre("j0", "j1", "j2", "j3"));
  EXPECT_EQ(a.arms[0].position_rad.size(), 4);
  // The grippers' openings are reported (open at the start, whatever they hold at the end).
  EXPECT_GT(sink_->arms.front().arms[0].gripper_aperture_m, 0.0);
  EXPECT_GT(sink_->arms.front().arms[1].gripper_aperture_m, 0.0);
}

TEST_F(MissionTelemetryTest, PosesImagesTransitionsAndTheFollowedPair) {
  ASSERT_GT(sink_->poses.size(), 100u);
  EXPECT_EQ(sink_->images, static_cast<int>(sink_->poses.size()));
  int found = 0;
  for (const TelemetryObjectPose& p : sink_->poses) {
    EXPECT_EQ(p.frame_id, "world");
    if (!p.found) continue;
    ++found;
    ASSERT_TRUE(p.covariance.has_value());
    EXPECT_GT((*p.covariance)(0, 0), 0.0);
    // Near the approach waypoint's view of the pipe: metres ahead, below the vehicle.
    EXPECT_LT(p.fMo.translation().norm(), 10.0);
  }
  EXPECT_GT(found, 100);
  ASSERT_FALSE(sink_->transitions.empty());
  EXPECT_EQ(sink_->transitions.front().machine, "global");
  EXPECT_EQ(sink_->transitions.front().cause, "start");
  ASSERT_FALSE(sink_->pairs.empty());
  // The first pair followed: a contact pair per arm, from the planner's ranking.
  EXPECT_GE(sink_->pairs.front().left_pair, 0);
  EXPECT_GE(sink_->pairs.front().right_pair, 0);
  EXPECT_THAT(sink_->pairs.front().reason, HasSubstr("ranked"));
  EXPECT_FALSE(sink_->log.empty());
}

// A command writes into a fresh temporary report folder, so an unwritable log
// is made here by hand: the command is told once and gets no sink, so it runs
// as with --no-mcap.
TEST(TelemetryOptionsTest, AnUnwritableLogIsSaidOnceAndLeavesNoSink) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("aerograsp_mission_nomcap_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "mission.mcap");  // a folder where the log should go
  TelemetryOptions options;
  std::vector<std::string> notes;
  CommandTelemetry t = OpenTelemetry(LoadTelemetryConfig(options), dir.string(), "mission",
                                     [&](const std::string& line) { notes.push_back(line); });
  EXPECT_EQ(t.sink(), nullptr);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_THAT(notes[0], HasSubstr("no MCAP log: " + (dir / "mission.mcap").string()));
  EXPECT_THAT(notes[0], HasSubstr("the run goes on without it"));
  EXPECT_EQ(t.Close(), "");
  fs::remove_all(dir);
}

TEST(TelemetryOptionsTest, NoMcapTurnsTheLogOff) {
  TelemetryOptions options;
  EXPECT_TRUE(LoadTelemetryConfig(options).mcap.enabled);
  options.no_mcap = true;
  const TelemetryConfig config = LoadTelemetryConfig(options);
  EXPECT_FALSE(config.mcap.enabled);
  EXPECT_EQ(OpenTelemetry(config, "/nonexistent", "mission", nullptr).sink(), nullptr);
}

}  // namespace
}  // namespace aerograsp
