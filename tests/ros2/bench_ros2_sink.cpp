// What publishing on ROS 2 costs the mission's loop: the bridge's calls of one
// servo cycle (both arms' joints, the moving transforms, /clock) and of one
// camera frame (the object's pose with its covariance, and a 640x480 colour
// and depth image when one is due), with nobody subscribed and with the Fast
// DDS peer subscribed (tests/peers/ros2/ros2_peer, started by the benchmark).
// Loopback only (data/dds/cyclonedds_loopback.xml). Not run by ctest:
//   build/tests/aerograsp_ros2_benchmarks [--benchmark_out=FILE.json --benchmark_out_format=json]
#include <benchmark/benchmark.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <memory>
#include <string>
#include <vector>

#include "ros2/ros2_bridge.h"

extern char** environ;

namespace aerograsp {
namespace {

constexpr double kServoPeriodS = 0.01;         // the mission's servo_rate_hz 100
constexpr double kCameraPeriodS = 1.0 / 30.0;  // the simulated D435

/// A bridge on `domain`, with the Fast DDS peer listening when `subscribed`.
class Setup {
 public:
  Setup(int domain, bool subscribed) {
    Ros2Config config;
    config.enabled = true;
    config.domain_id = domain;
    config.dds_config = std::string(AEROGRASP_DATA_DIR) + "/dds/cyclonedds_loopback.xml";
    bridge_ = OpenRos2(config, [](const std::string&) {});
    if (!subscribed) return;
    const std::vector<std::string> argv = {
        AEROGRASP_ROS2_PEER, "listen", std::to_string(domain), "aerograsp", "/dev/null",
        "--timeout-s",       "600"};
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (posix_spawn(&peer_, args[0], nullptr, nullptr, args.data(), environ) != 0) peer_ = -1;
    WaitForSubscribers(bridge_, 1, 30.0);
  }
  ~Setup() {
    bridge_ = {};
    if (peer_ > 0) {
      kill(peer_, SIGTERM);
      waitpid(peer_, nullptr, 0);
    }
  }
  TelemetrySink& sink() { return *bridge_.sink; }
  bool ok() const { return static_cast<bool>(bridge_); }

 private:
  Ros2Bridge bridge_;
  pid_t peer_ = -1;
};

TelemetryArms Arms() {
  TelemetryArms arms;
  for (int a = 0; a < 2; ++a) {
    arms.arms[a].arm = a == 0 ? "left" : "right";
    arms.arms[a].joint_names = {"j0", "j1", "j2", "j3"};
    arms.arms[a].position_rad = Eigen::Vector4d(0.1, -0.2, 0.3, -0.4);
    arms.arms[a].target_rad = Eigen::Vector4d(0.1, -0.2, 0.3, -0.4);
    arms.arms[a].gripper_aperture_m = 0.06;
  }
  return arms;
}

void ServoCycle(benchmark::State& state, bool subscribed) {
  Setup setup(90 + static_cast<int>(subscribed), subscribed);
  if (!setup.ok()) {
    state.SkipWithError("no DDS");
    return;
  }
  TelemetryArms arms = Arms();
  std::vector<TelemetryTransform> tf = {
      {"world", "body", Eigen::Isometry3d::Identity()},
      {"arm_left_mount", "arm_left_tool", Eigen::Isometry3d::Identity()},
      {"arm_right_mount", "arm_right_tool", Eigen::Isometry3d::Identity()},
      {"world", "object", Eigen::Isometry3d::Identity()}};
  double t = 0.0;
  for (auto _ : state) {
    t += kServoPeriodS;
    arms.t_s = t;
    setup.sink().Arms(arms);
    setup.sink().Transforms(t, tf);
  }
}

void CameraFrame(benchmark::State& state, bool subscribed) {
  Setup setup(92 + static_cast<int>(subscribed), subscribed);
  if (!setup.ok()) {
    state.SkipWithError("no DDS");
    return;
  }
  ColorImage color(640, 480, 90);
  DepthImage depth(640, 480, 800);
  TelemetryObjectPose pose;
  pose.frame_id = "world";
  pose.valid = pose.found = true;
  pose.covariance = Eigen::Matrix<double, 6, 6>::Identity() * 1e-6;
  TelemetryImage image;
  image.color = &color;
  image.depth = &depth;
  double t = 0.0;
  for (auto _ : state) {
    t += kCameraPeriodS;
    pose.t_s = image.t_s = t;
    setup.sink().ObjectPose(pose);
    setup.sink().Image(image);  // at image_rate_hz (5 Hz): one frame in six
  }
}

BENCHMARK_CAPTURE(ServoCycle, no_subscriber, false)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(ServoCycle, peer_subscribed, true)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(CameraFrame, no_subscriber, false)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(CameraFrame, peer_subscribed, true)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace aerograsp

BENCHMARK_MAIN();
