// Every fault the simulated devices produce, staged as a hardware file stages
// it (from a time of the simulated clock on), seen through the real drivers
// where there is one: the SCS driver on the simulated bus, the PX4 client on
// the simulated PX4; the simulated camera and the world's object.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>

#include "core/config.h"
#include "core/data_dir.h"
#include "hardware/device_health.h"
#include "hardware/hardware_config.h"
#include "hardware/mavlink/px4_autopilot.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/sim_px4.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

constexpr double kCycle_s = 0.01;

WorldConfig DefaultWorld() { return WorldConfig::Load(DataPath("config/world_default.yaml")); }

/// The SCS driver on a simulated bus with `faults`, on the simulated clock.
class BusFaultsTest : public ::testing::Test {
 protected:
  BusFaultsTest() : world_(DefaultWorld(), 1) {}
  void Open(SimServoBusConfig faults) {
    servos_ = ScsArmsConfig::Default(world_.platform());
    faults.byte_time_s = 0.0;
    faults.return_delay_s = 0.0;
    bus_ = std::make_unique<SimServoBus>(&world_, servos_, faults);
    servos_.port = bus_->port_path();
    servos_.reply_timeout_s = 0.2;  // generous: a late thread is not a fault
    driver_ = std::make_unique<ScsArmsDriver>(world_.platform(), servos_,
                                              [this] { return world_.now_s(); });
  }
  void Run(double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kCycle_s)); ++i) {
      driver_->Cycle();
      bus_->SyncWithWorld();
      world_.Step(kCycle_s);
    }
  }
  ScsServoStatus Status(int id) const {
    for (const ScsServoStatus& s : driver_->servo_statuses())
      if (s.id == id) return s;
    return {};
  }
  World world_;
  ScsArmsConfig servos_;
  std::unique_ptr<SimServoBus> bus_;
  std::unique_ptr<ScsArmsDriver> driver_;
};

TEST_F(BusFaultsTest, HotAndLowVoltageServosReportItFromTheirTime) {
  SimServoBusConfig faults;
  faults.hot_ids = {21};
  faults.low_voltage_ids = {14};
  faults.faults_from_s = 0.2;
  Open(faults);
  Run(0.15);  // every servo's status read at least once (ten servos, one a cycle)
  EXPECT_EQ(Status(21).temperature_c, 35);
  EXPECT_NEAR(Status(14).voltage_v, 7.4, 1e-9);
  EXPECT_LT(bus_->faults_on_since_s(), 0.0);
  Run(0.15);
  EXPECT_EQ(Status(21).temperature_c, 85);
  EXPECT_NEAR(Status(14).voltage_v, 5.0, 1e-9);
  EXPECT_NEAR(bus_->faults_on_since_s(), 0.2, kCycle_s + 1e-9);
}

TEST_F(BusFaultsTest, SilentServoFailsEveryReadFromItsTime) {
  SimServoBusConfig faults;
  faults.silent_ids = {12};
  faults.faults_from_s = 0.095;  // between two cycles
  Open(faults);
  Run(0.1);
  EXPECT_EQ(Status(12).failed_reads, 0);
  const std::int64_t good = Status(12).good_reads;
  Run(0.05);
  EXPECT_GE(Status(12).failed_reads, 4);
  EXPECT_EQ(Status(12).good_reads, good + 1);  // the cycle at 0.1 s ran before the switch
  EXPECT_EQ(Status(13).failed_reads, 0);
}

TEST_F(BusFaultsTest, OffsetServoReadsOffByItsAngle) {
  SimServoBusConfig faults;
  faults.offset_ids = {12};
  faults.offset_deg = 30.0;
  faults.faults_from_s = 0.05;
  Open(faults);
  Run(0.5);  // the arm has settled where the servo takes its goal to be
  const double measured = driver_->JointPositions(Side::kLeft)[1];
  const double truth = world_.arm(Side::kLeft).q_true_rad()[1];
  EXPECT_NEAR(measured - truth, 30.0 * M_PI / 180.0, 2.0 * world_.arm(Side::kLeft).quantum_rad());
}

TEST_F(BusFaultsTest, AServoWithItsSensorOffIsHeldWhereItIsByTheStop) {
  // Its reading is 60 deg more than where it is, and it goes to 60 deg less
  // than its goal (its control loop uses the same sensor): holding its
  // reading holds it where that reading was taken, a cycle before the stop.
  SimServoBusConfig faults;
  faults.offset_ids = {12};
  faults.offset_deg = 60.0;
  faults.faults_from_s = 0.05;
  Open(faults);
  Run(0.1);
  driver_->Stop();
  const double at_stop = world_.arm(Side::kLeft).q_true_rad()[1];
  Run(1.0);  // long enough for the arm to reach any goal it was sent
  EXPECT_NEAR(world_.arm(Side::kLeft).q_true_rad()[1], at_stop, 0.15);  // one cycle's motion
  EXPECT_NEAR(driver_->JointPositions(Side::kLeft)[1] - world_.arm(Side::kLeft).q_true_rad()[1],
              60.0 * M_PI / 180.0, 2.0 * world_.arm(Side::kLeft).quantum_rad());
}

TEST_F(BusFaultsTest, CorruptionStartsAtItsTime) {
  SimServoBusConfig faults;
  faults.corrupt_probability = 0.05;
  faults.faults_from_s = 0.1;
  Open(faults);
  Run(0.1);
  EXPECT_EQ(bus_->counters().corrupted_bytes, 0);
  EXPECT_EQ(driver_->counters().bad_checksums, 0);
  Run(0.2);
  EXPECT_GT(bus_->counters().corrupted_bytes, 0);
  EXPECT_GT(driver_->counters().bad_checksums, 0);
}

/// The PX4 client against the simulated PX4 with faults.
class Px4FaultsTest : public ::testing::Test {
 protected:
  Px4FaultsTest() : world_(DefaultWorld(), 1) {}
  void Open(const SimPx4Faults& faults) {
    SimPx4Config peer;
    peer.faults = faults;
    peer_ = std::make_unique<SimPx4>(&world_, peer);
    Px4Config config;
    config.command_timeout_s = 0.5;  // generous: a late thread is not a fault
    client_ = std::make_unique<Px4Autopilot>(
        std::make_unique<UdpLink>("127.0.0.1", 0, "127.0.0.1", peer_->port(), "autopilot"), config,
        [this] { return world_.now_s(); });
    client_->Connect();
  }
  void Run(double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kCycle_s)); ++i) {
      peer_->StepWorld(kCycle_s);
      client_->Spin();
    }
  }
  World world_;
  std::unique_ptr<SimPx4> peer_;
  std::unique_ptr<Px4Autopilot> client_;
};

TEST_F(Px4FaultsTest, CommandsRefusedFromTheirTime) {
  SimPx4Faults faults;
  faults.reject_commands = true;
  faults.faults_from_s = 0.2;
  Open(faults);
  Run(0.1);
  EXPECT_TRUE(client_->Hold().accepted);
  EXPECT_LT(peer_->first_fault_s(), 0.0);
  Run(0.2);
  const CommandAck ack = client_->Hold();
  EXPECT_FALSE(ack.accepted);
  EXPECT_NE(ack.reason.find("command refused (simulated fault)"), std::string::npos) << ack.reason;
  EXPECT_NEAR(peer_->first_fault_s(), world_.now_s(), 1e-9);
}

TEST_F(Px4FaultsTest, SilentFromItsTime) {
  SimPx4Faults faults;
  faults.silent = true;
  faults.faults_from_s = 0.2;
  Open(faults);
  Run(0.15);
  const double stamp = client_->State().stamp_s;
  EXPECT_GT(stamp, 0.1);
  Run(0.3);
  EXPECT_LT(client_->State().stamp_s, 0.2 + 1e-9);  // nothing new since the link fell silent
  EXPECT_NEAR(peer_->first_fault_s(), 0.2, kCycle_s + 1e-9);
}

TEST(SimCameraFaultsTest, FrozenRepeatsTheLastFrame) {
  World world(DefaultWorld(), 1);
  SimCameraFaults faults;
  faults.frozen = true;
  faults.faults_from_s = 0.05;
  SimCamera camera(&world, faults);
  RgbdFrame first, second;
  ASSERT_TRUE(camera.Grab(&first));
  world.Step(0.1);
  ASSERT_TRUE(camera.Grab(&second));
  EXPECT_EQ(second.index, first.index);
  EXPECT_EQ(second.stamp_s, first.stamp_s);
  EXPECT_TRUE(second.depth == first.depth);
  EXPECT_NEAR(camera.first_fault_s(), 0.1, 1e-9);
}

TEST(SimCameraFaultsTest, NoDepthFromItsTime) {
  World world(DefaultWorld(), 1);
  SimCameraFaults faults;
  faults.no_depth = true;
  faults.faults_from_s = 0.05;
  SimCamera camera(&world, faults);
  RgbdFrame frame;
  ASSERT_TRUE(camera.Grab(&frame));
  EXPECT_TRUE(DepthHasData(frame.depth));
  world.Step(0.1);
  ASSERT_TRUE(camera.Grab(&frame));
  EXPECT_FALSE(DepthHasData(frame.depth));
  EXPECT_EQ(frame.index, 1);
}

TEST(WorldFaultsTest, ObjectKnockedOffThePipeLandsOnTheGround) {
  WorldConfig config = DefaultWorld();
  config.object.knocked_off_at_s = 0.1;
  World world(config, 1);
  const Eigen::Vector3d on_pipe = world.wMo().translation();
  world.Step(0.05);
  EXPECT_TRUE(world.wMo().translation().isApprox(on_pipe));
  world.Step(0.1);
  const Eigen::Vector3d after = world.wMo().translation();
  EXPECT_NEAR((after - on_pipe).head<2>().norm(), 0.5, 0.05);
  EXPECT_GT(after.z(), -0.3);  // NED: near the ground (z = 0), well below the pipe
}

TEST(HardwareFaultsConfigTest, EveryFaultAndBoundIsReadFromTheFile) {
  const std::string path = ::testing::TempDir() + "/hw_faults.yaml";
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms:\n  backend: sim-bus\n  sim_bus: {silent_ids: [12], slow_ids: [13], "
                         "hot_ids: [21], low_voltage_ids: [14], offset_ids: [22], offset_deg: -20, "
                         "hot_temperature_c: 90, low_voltage_v: 5.5, corrupt_probability: 0.01, "
                         "faults_from_s: 6}\n"
                      << "autopilot:\n  sim_px4: {faults_from_s: 7, silent: true, "
                         "reject_commands: true}\n"
                      << "camera:\n  sim: {faults_from_s: 8, frozen: true, no_depth: true}\n"
                      << "health: {servo_max_failed_reads: 5, camera_max_frame_age_s: 0.2}\n";
  const HardwareConfig c = HardwareConfig::Load(path);
  EXPECT_EQ(c.arms.sim_bus.silent_ids, std::vector<int>{12});
  EXPECT_EQ(c.arms.sim_bus.slow_ids, std::vector<int>{13});
  EXPECT_EQ(c.arms.sim_bus.hot_ids, std::vector<int>{21});
  EXPECT_EQ(c.arms.sim_bus.low_voltage_ids, std::vector<int>{14});
  EXPECT_EQ(c.arms.sim_bus.offset_ids, std::vector<int>{22});
  EXPECT_EQ(c.arms.sim_bus.offset_deg, -20.0);
  EXPECT_EQ(c.arms.sim_bus.hot_temperature_c, 90);
  EXPECT_EQ(c.arms.sim_bus.low_voltage_v, 5.5);
  EXPECT_EQ(c.arms.sim_bus.faults_from_s, 6.0);
  EXPECT_EQ(c.autopilot.sim_px4.faults_from_s, 7.0);
  EXPECT_TRUE(c.autopilot.sim_px4.silent);
  EXPECT_TRUE(c.autopilot.sim_px4.reject_commands);
  EXPECT_EQ(c.camera.sim.faults_from_s, 8.0);
  EXPECT_TRUE(c.camera.sim.frozen);
  EXPECT_TRUE(c.camera.sim.no_depth);
  EXPECT_EQ(c.health.servo_max_failed_reads, 5);
  EXPECT_EQ(c.health.camera_max_frame_age_s, 0.2);
}

TEST(HardwareFaultsConfigTest, BadFaultAndHealthValuesNameTheirKey) {
  const auto error_of = [](const std::string& name, const std::string& body) {
    const std::string path = ::testing::TempDir() + "/" + name;
    std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                        << "world: " << DataPath("config/world_default.yaml") << "\n"
                        << body;
    try {
      HardwareConfig::Load(path);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of("hw_f1.yaml", "autopilot: {sim_px4: {lost: true}}\n").find("lost"),
            std::string::npos);
  EXPECT_NE(error_of("hw_f2.yaml", "camera: {sim: {faults_from_s: -1}}\n")
                .find("hw_f2.yaml: camera.sim.faults_from_s"),
            std::string::npos);
  EXPECT_NE(error_of("hw_f3.yaml", "health: {bus_max_error_rate: 2}\n")
                .find("hw_f3.yaml: health.bus_max_error_rate"),
            std::string::npos);
  EXPECT_NE(error_of("hw_f4.yaml", "arms: {sim_bus: {hot_ids: [300]}}\n").find("hot_ids"),
            std::string::npos);
}

}  // namespace
}  // namespace aerograsp
