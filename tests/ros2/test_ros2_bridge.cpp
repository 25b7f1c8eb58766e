// The ROS 2 bridge against the independent Fast DDS peer (tests/peers/ros2/ros2_peer),
// on loopback only (data/dds/cyclonedds_loopback.xml). Each test has its own DDS domain.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "core/config.h"
#include "ros2/ros2_bridge.h"

extern char** environ;

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kPeer = AEROGRASP_ROS2_PEER;
const std::string kLoopback = std::string(AEROGRASP_DATA_DIR) + "/dds/cyclonedds_loopback.xml";

Ros2Config Loopback(int domain) {
  Ros2Config c;
  c.enabled = true;
  c.domain_id = domain;
  c.dds_config = kLoopback;
  return c;
}

/// A child process, ended (SIGKILL) and reaped when it goes out of scope.
class Child {
 public:
  explicit Child(const std::vector<std::string>& argv) {
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (posix_spawn(&pid_, args[0], nullptr, nullptr, args.data(), environ) != 0) pid_ = -1;
  }
  ~Child() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  bool started() const { return pid_ > 0; }
  /// Waits for the exit; its status, or -1.
  int Wait() {
    int status = 0;
    if (pid_ <= 0 || waitpid(pid_, &status, 0) != pid_) return -1;
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
};

/// Polls `source` until a stop or `timeout_s`; the notes seen on the way go to `notes`.
EmergencyStopPoll PollUntilStop(EmergencyStopSource& source, double timeout_s,
                                std::vector<std::string>* notes) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  EmergencyStopPoll poll;
  while (std::chrono::steady_clock::now() < deadline) {
    poll = source.Poll(0.0);
    notes->insert(notes->end(), poll.notes.begin(), poll.notes.end());
    if (poll.stop) return poll;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return poll;
}

TEST(Ros2ConfigTest, ShippedFileEqualsTheDefaults) {
  const Ros2Config shipped =
      TelemetryConfig::Load(std::string(AEROGRASP_DATA_DIR) + "/config/telemetry.yaml").ros2;
  const Ros2Config defaults;
  EXPECT_EQ(shipped.enabled, defaults.enabled);
  EXPECT_EQ(shipped.domain_id, defaults.domain_id);
  EXPECT_EQ(shipped.topic_namespace, defaults.topic_namespace);
  EXPECT_EQ(shipped.dds_config, defaults.dds_config);
  EXPECT_EQ(shipped.joint_states_rate_hz, defaults.joint_states_rate_hz);
  EXPECT_EQ(shipped.image_rate_hz, defaults.image_rate_hz);
  EXPECT_EQ(shipped.publish_clock, defaults.publish_clock);
  EXPECT_EQ(shipped.emergency_stop_wait_s, defaults.emergency_stop_wait_s);
}

TEST(Ros2ConfigTest, BadValuesAreRefusedWithTheirKey) {
  const fs::path file = fs::temp_directory_path() / ("aerograsp_ros2_" + std::to_string(getpid()));
  const auto load_error = [&](const std::string& yaml) {
    std::ofstream(file) << yaml;
    try {
      TelemetryConfig::Load(file.string());
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(load_error("ros2:\n  domain_id: 233\n"),
              HasSubstr("ros2.domain_id: 233 is above the upper bound 232"));
  EXPECT_THAT(load_error("ros2:\n  topic_namespace: /aerograsp\n"),
              HasSubstr("ros2.topic_namespace: '/aerograsp' must not start with '/'"));
  EXPECT_THAT(load_error("ros2:\n  topic_namespace: aero-grasp\n"),
              HasSubstr("is not a letter, digit"));
  EXPECT_THAT(load_error("ros2:\n  image_rate_hz: -1\n"), HasSubstr("ros2.image_rate_hz: -1 Hz"));
  EXPECT_THAT(load_error("ros2:\n  dds_config: missing.xml\n"), HasSubstr("ros2.dds_config: file"));
  EXPECT_THAT(load_error("ros2:\n  domain: 3\n"), HasSubstr("ros2.domain"));
  EXPECT_THAT(load_error("ros2:\n  enabled: maybe\n"), HasSubstr("ros2.enabled"));
  fs::remove(file);
}

TEST(Ros2BridgeTest, DisabledOpensNothing) {
  std::vector<std::string> notes;
  const Ros2Bridge bridge =
      OpenRos2(Ros2Config{}, [&](const std::string& l) { notes.push_back(l); });
  EXPECT_FALSE(bridge);
  EXPECT_EQ(bridge.emergency_stop, nullptr);
  EXPECT_TRUE(notes.empty());
}

TEST(Ros2BridgeTest, NoUsableNetworkIsSaidOnceAndTheCommandGoesOn) {
  // A DDS configuration naming an interface this machine does not have.
  const fs::path xml =
      fs::temp_directory_path() / ("aerograsp_no_net_" + std::to_string(getpid()) + ".xml");
  std::ofstream(xml) << "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>"
                        "<NetworkInterface name=\"aerograsp_no_such_if0\"/>"
                        "</Interfaces></General></Domain></CycloneDDS>\n";
  Ros2Config config = Loopback(72);
  config.dds_config = xml.string();
  std::vector<std::string> notes;
  const Ros2Bridge bridge = OpenRos2(config, [&](const std::string& l) { notes.push_back(l); });
  fs::remove(xml);
  EXPECT_FALSE(bridge);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_THAT(notes[0], HasSubstr("ROS 2: cannot join DDS domain 72"));
  EXPECT_THAT(notes[0], HasSubstr("going on without ROS 2 topics"));
}

TEST(Ros2BridgeTest, StopFromTheIndependentPeerIsLatchedWithItsSource) {
  std::vector<std::string> notes;
  Ros2Bridge bridge = OpenRos2(Loopback(73), [&](const std::string& l) { notes.push_back(l); });
  ASSERT_TRUE(bridge);
  EXPECT_FALSE(bridge.emergency_stop->Poll(0.0).stop);
  Child peer({kPeer, "estop", "73", "aerograsp"});
  ASSERT_TRUE(peer.started());
  const EmergencyStopPoll poll = PollUntilStop(*bridge.emergency_stop, 30.0, &notes);
  ASSERT_TRUE(poll.stop);
  EXPECT_THAT(poll.source, HasSubstr("ROS 2 /aerograsp/emergency_stop (writer "));
  EXPECT_EQ(poll.reason, "std_msgs/Bool true");
  EXPECT_EQ(peer.Wait(), 0);
  EXPECT_TRUE(bridge.emergency_stop->Poll(1.0).stop);  // latched
}

TEST(Ros2BridgeTest, MalformedStopIsSaidAndIgnoredThenARealOneStops) {
  std::vector<std::string> notes;
  Ros2Bridge bridge = OpenRos2(Loopback(74), [&](const std::string& l) { notes.push_back(l); });
  ASSERT_TRUE(bridge);
  {
    Child bad({kPeer, "estop", "74", "aerograsp", "--malformed"});
    ASSERT_EQ(bad.Wait(), 0);  // acknowledged by our reader
  }
  std::vector<std::string> seen;
  EmergencyStopPoll poll = bridge.emergency_stop->Poll(0.0);
  seen.insert(seen.end(), poll.notes.begin(), poll.notes.end());
  EXPECT_FALSE(poll.stop);
  Child good({kPeer, "estop", "74", "aerograsp"});
  poll = PollUntilStop(*bridge.emergency_stop, 30.0, &seen);
  EXPECT_TRUE(poll.stop);
  ASSERT_EQ(seen.size(), 1u) << ::testing::PrintToString(seen);
  EXPECT_THAT(seen[0], HasSubstr("malformed"));
}

TEST(Ros2BridgeTest, PortInUseTakesTheNextParticipantIndex) {
  // Domain 75's first participant index: its discovery and data ports on 127.0.0.1.
  const int domain = 75;
  int sockets[2];
  for (int i = 0; i < 2; ++i) {
    sockets[i] = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(7400 + 250 * domain + 10 + i));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(bind(sockets[i], reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  }
  std::vector<std::string> notes;
  Ros2Bridge bridge = OpenRos2(Loopback(domain), [&](const std::string& l) { notes.push_back(l); });
  ASSERT_TRUE(bridge) << ::testing::PrintToString(notes);
  Child peer({kPeer, "estop", std::to_string(domain), "aerograsp"});
  EXPECT_TRUE(PollUntilStop(*bridge.emergency_stop, 30.0, &notes).stop);
  for (int s : sockets) close(s);
}

TEST(Ros2BridgeTest, SubscriberThatDisappearsIsSaidOnceAndPublishingGoesOn) {
  const fs::path out = fs::temp_directory_path() / ("aerograsp_left_" + std::to_string(getpid()));
  std::vector<std::string> notes;
  Ros2Config config = Loopback(76);
  config.image_rate_hz = 0;
  Ros2Bridge bridge = OpenRos2(config, [&](const std::string& l) { notes.push_back(l); });
  ASSERT_TRUE(bridge);
  // The peer takes 50 messages and dies without a goodbye, as a crashed node does.
  Child peer({kPeer, "listen", "76", "aerograsp", out.string(), "--no-images", "--leave-after",
              "50", "--lease-s", "1"});
  ASSERT_TRUE(WaitForSubscribers(bridge, 1, 30.0));
  TelemetryArms arms;
  for (int a = 0; a < 2; ++a) {
    arms.arms[a].arm = a == 0 ? "left" : "right";
    arms.arms[a].joint_names = {"j0", "j1", "j2", "j3"};
    arms.arms[a].position_rad = Eigen::Vector4d::Zero();
  }
  // Publishing at 100 Hz of mission time, as fast as it goes, until DDS has
  // said that the subscriber left (its lease is 1 s) or 60 s of wall time.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  const auto left = [&] {
    for (const std::string& n : notes)
      if (n.find("ROS 2: a subscriber of") != std::string::npos &&
          n.find(" left (") != std::string::npos)
        return true;
    return false;
  };
  long calls = 0;
  while (!left() && std::chrono::steady_clock::now() < deadline) {
    arms.t_s = 0.01 * calls++;
    bridge.sink->Arms(arms);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  EXPECT_EQ(peer.Wait(), 0);
  EXPECT_TRUE(left()) << ::testing::PrintToString(notes);
  // Each thing said once per topic.
  std::map<std::string, int> counts;
  for (const std::string& n : notes) ++counts[n];
  for (const auto& [line, n] : counts) EXPECT_EQ(n, 1) << line;
  bridge.sink->Close();
  fs::remove(out);
}

}  // namespace
}  // namespace aerograsp
