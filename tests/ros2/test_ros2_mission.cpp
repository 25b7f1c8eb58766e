// A simulated mission publishing on ROS 2 and stopped from the outside: the
// independent Fast DDS peer (tests/peers/ros2/ros2_peer) listens, and when the
// arms start moving it sends a malformed std_msgs/Bool and then a real `true`
// on /aerograsp/emergency_stop. Loopback only, domain 82.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "app/runtime/mission_runner.h"
#include "ros2/ros2_bridge.h"
#include "tests/common/joint_travel.h"

extern char** environ;

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using aerograsp::testing::JointTravel;
using ::testing::HasSubstr;

constexpr int kDomain = 82;

/// Keeps the arms and the transitions the mission sends.
class ArmsRecorder final : public TelemetrySink {
 public:
  std::vector<TelemetryArms> arms;
  std::vector<TelemetryTransition> transitions;
  void StaticTransforms(double, const std::vector<TelemetryTransform>&) override {}
  void Transforms(double, const std::vector<TelemetryTransform>&) override {}
  void ObjectPose(const TelemetryObjectPose&) override {}
  void Arms(const TelemetryArms& a) override { arms.push_back(a); }
  void Transition(const TelemetryTransition& t) override { transitions.push_back(t); }
  void GraspPair(const TelemetryGraspPair&) override {}
  void Image(const TelemetryImage&) override {}
  void Log(double, TelemetryLevel, const std::string&, const std::string&) override {}
  void Close() override {}
};

/// Passes the polls on and keeps the mission time of the first that found a stop.
class FirstStop final : public EmergencyStopSource {
 public:
  explicit FirstStop(EmergencyStopSource* inner) : inner_(inner) {}
  EmergencyStopPoll Poll(double t_s) override {
    EmergencyStopPoll poll = inner_->Poll(t_s);
    if (poll.stop && first_s < 0) first_s = t_s;
    return poll;
  }
  double first_s = -1.0;

 private:
  EmergencyStopSource* inner_;
};

class Ros2MissionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir =
        fs::temp_directory_path() / ("aerograsp_ros2_mission_" + std::to_string(getpid()));
    fs::create_directories(dir);
    Ros2Config config;
    config.enabled = true;
    config.domain_id = kDomain;
    config.dds_config = std::string(AEROGRASP_DATA_DIR) + "/dds/cyclonedds_loopback.xml";
    config.image_rate_hz = 0;
    FanOutSink sinks;
    const auto note = [](const std::string& line) { log_ << "telemetry: " << line << "\n"; };
    Ros2Bridge bridge = OpenRos2(config, note);
    ASSERT_TRUE(bridge) << log_.str();
    sinks.Add(std::move(bridge.sink));
    const std::unique_ptr<EmergencyStopSource> ros2_stop = std::move(bridge.emergency_stop);
    recorder_ = new ArmsRecorder;
    sinks.Add(std::unique_ptr<TelemetrySink>(new ForwardTo(recorder_)));

    const std::string ready = (dir / "ready").string();
    const std::vector<std::string> argv = {AEROGRASP_ROS2_PEER,
                                           "listen",
                                           std::to_string(kDomain),
                                           "aerograsp",
                                           (dir / "received.jsonl").string(),
                                           "--no-images",
                                           "--estop-on",
                                           "arms: idle -> moving",
                                           "--malformed-first",
                                           "--until",
                                           "mission failed",
                                           "--timeout-s",
                                           "120",
                                           "--ready-file",
                                           ready};
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t peer = -1;
    ASSERT_EQ(posix_spawn(&peer, args[0], nullptr, nullptr, args.data(), environ), 0);
    // The peer hears every topic before the mission starts.
    for (int i = 0; i < 3000 && !fs::exists(ready); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(fs::exists(ready)) << "the peer did not get ready";

    stop_ = new FirstStop(ros2_stop.get());
    MissionOptions m;
    m.seed = 1;
    m.object = "u_shape";  // the arms servo from about 12.8 s of mission time
    m.timeout_s = 25.0;
    MissionLinks links;
    links.telemetry = &sinks;
    links.emergency_stop = stop_;
    result_ = RunMission(m, nullptr, &log_, links);
    sinks.Close();
    int status = 0;
    waitpid(peer, &status, 0);
    peer_exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    fs::remove_all(dir);
  }
  static void TearDownTestSuite() {
    delete recorder_;
    delete stop_;
  }

  /// Hands the calls to a recorder the test suite keeps after the sinks are gone.
  class ForwardTo final : public TelemetrySink {
   public:
    explicit ForwardTo(TelemetrySink* to) : to_(to) {}
    void StaticTransforms(double t, const std::vector<TelemetryTransform>& x) override {
      to_->StaticTransforms(t, x);
    }
    void Transforms(double t, const std::vector<TelemetryTransform>& x) override {
      to_->Transforms(t, x);
    }
    void ObjectPose(const TelemetryObjectPose& x) override { to_->ObjectPose(x); }
    void Arms(const TelemetryArms& x) override { to_->Arms(x); }
    void Transition(const TelemetryTransition& x) override { to_->Transition(x); }
    void GraspPair(const TelemetryGraspPair& x) override { to_->GraspPair(x); }
    void Image(const TelemetryImage& x) override { to_->Image(x); }
    void Log(double t, TelemetryLevel l, const std::string& n, const std::string& s) override {
      to_->Log(t, l, n, s);
    }
    void Close() override { to_->Close(); }

   private:
    TelemetrySink* to_;
  };

  static ArmsRecorder* recorder_;
  static FirstStop* stop_;
  static std::ostringstream log_;
  static MissionResult result_;
  static int peer_exit_;
};

ArmsRecorder* Ros2MissionTest::recorder_ = nullptr;
FirstStop* Ros2MissionTest::stop_ = nullptr;
std::ostringstream Ros2MissionTest::log_;
MissionResult Ros2MissionTest::result_;
int Ros2MissionTest::peer_exit_ = -1;

// One test: ctest runs each test in a process of its own, and one mission
// with its peer is what is looked at from every side.
TEST_F(Ros2MissionTest, PeersStopAfterAMalformedOneStopsTheArmsInTheCycleThatHearsIt) {
  // The mission's emergency, with the source and its DDS writer.
  EXPECT_EQ(peer_exit_, 0);
  EXPECT_FALSE(result_.success);
  EXPECT_EQ(result_.emergency_stops, 1);
  EXPECT_THAT(result_.failure,
              HasSubstr("emergency stop from ROS 2 /aerograsp/emergency_stop (writer "));
  const std::string log = log_.str();
  EXPECT_THAT(log, HasSubstr("emergency stop requested by ROS 2 /aerograsp/emergency_stop"));

  // The malformed one before it: said once, and it did not stop anything.
  const std::string malformed = "a malformed message from writer";
  const std::size_t first = log.find(malformed);
  ASSERT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find(malformed, first + 1), std::string::npos) << log;
  EXPECT_LT(first, log.find("emergency stop requested by ROS 2"));

  // The arms stopped in the servo cycle whose poll found the request, while servoing.
  const double t_stop = stop_->first_s;
  ASSERT_GT(t_stop, 0.0) << log;
  bool stopped = false;
  for (const TelemetryTransition& t : recorder_->transitions) {
    if (t.machine != "arms" || t.to != "emergency stop") continue;
    EXPECT_DOUBLE_EQ(t.t_s, t_stop);
    EXPECT_EQ(t.from, "moving");
    stopped = true;
  }
  EXPECT_TRUE(stopped) << log;
  // Still from the cycle after the stop's on (what moves is the servos' lag settling).
  EXPECT_LT(JointTravel(recorder_->arms, t_stop + 0.02, t_stop + 1.0), 2e-3);
}

}  // namespace
}  // namespace aerograsp
