// The SCS arm driver against the simulated servo bus over a pseudo-terminal,
// on the world's simulated clock.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "core/data_dir.h"
#include "hardware/device_health.h"
#include "hardware/rgbd_camera.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

constexpr double kCycle_s = 0.01;
constexpr double kDeg = M_PI / 180.0;

class ScsDriverTest : public ::testing::Test {
 protected:
  ScsDriverTest() : world_(WorldConfig::Load(DataPath("config/world_default.yaml")), 1) {
    servos_ = ScsArmsConfig::Default(world_.platform());
    // Generous: the bus answers at once from its own thread, which a loaded
    // machine may hold back for tens of ms. The bus learns it too: it decides
    // which replies the driver hears before its timeout.
    servos_.reply_timeout_s = 0.2;
    SimServoBusConfig bus_config;
    bus_config.byte_time_s = 0.0;  // no wire timing: the tests are about behaviour
    bus_config.return_delay_s = 0.0;
    bus_ = std::make_unique<SimServoBus>(&world_, servos_, bus_config);
    servos_.port = bus_->port_path();
  }

  std::unique_ptr<ScsArmsDriver> Open() {
    return std::make_unique<ScsArmsDriver>(world_.platform(), servos_,
                                           [this] { return world_.now_s(); });
  }

  /// The closed loop: a bus cycle, the world's turn, the clock.
  void Run(ScsArmsDriver* driver, double seconds) {
    const int cycles = static_cast<int>(std::lround(seconds / kCycle_s));
    for (int i = 0; i < cycles; ++i) {
      driver->Cycle();
      bus_->SyncWithWorld();
      world_.Step(kCycle_s);
    }
  }

  /// Keeps sending `target` (fresh every cycle, as a servo loop would) for `seconds`.
  void Track(ScsArmsDriver* driver, Side side, const Eigen::VectorXd& target, double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kCycle_s)); ++i) {
      driver->SetJointTargets(side, target);
      Run(driver, kCycle_s);
    }
  }

  /// The last command with joint `joint` moved by `by_rad`.
  static Eigen::VectorXd Moved(const ScsArmsDriver& driver, Side side, int joint, double by_rad) {
    Eigen::VectorXd q = driver.last_command(side);
    q[joint] += by_rad;
    return q;
  }

  World world_;
  ScsArmsConfig servos_;
  std::unique_ptr<SimServoBus> bus_;
};

TEST_F(ScsDriverTest, OpensWithEveryServoAtItsPresentPositionAndTorqueOn) {
  auto driver = Open();
  const double quantum = world_.arm(Side::kLeft).quantum_rad();
  for (Side side : kSides) {
    EXPECT_LE((driver->JointPositions(side) - world_.arm(side).q_true_rad()).cwiseAbs().maxCoeff(),
              quantum);
  }
  Run(driver.get(), 0.02);
  EXPECT_EQ(bus_->Registers(11)[scs::reg::kTorqueEnable], 1);
  EXPECT_EQ(bus_->Registers(27)[scs::reg::kTorqueEnable], 1);
}

TEST_F(ScsDriverTest, JointsReachTheirTargetsThroughTheBus) {
  auto driver = Open();
  Eigen::VectorXd target = world_.platform().home(Side::kRight);
  target[0] += 0.3;
  target[1] -= 0.2;
  Track(driver.get(), Side::kRight, target, 1.5);
  const double quantum = world_.arm(Side::kRight).quantum_rad();
  EXPECT_LE((driver->JointPositions(Side::kRight) - target).cwiseAbs().maxCoeff(), 1.5 * quantum);
  EXPECT_LE((world_.arm(Side::kRight).q_true_rad() - target).cwiseAbs().maxCoeff(), 1.5 * quantum);
}

TEST_F(ScsDriverTest, CommandsMoveAtMostTwentyDegreesPerCycle) {
  auto driver = Open();
  const Eigen::VectorXd start = driver->last_command(Side::kLeft);
  driver->SetJointTargets(Side::kLeft, Moved(*driver, Side::kLeft, 0, 80.0 * kDeg));
  driver->Cycle();
  EXPECT_NEAR(driver->last_command(Side::kLeft)[0] - start[0], servos_.max_step_rad, 1e-12);
}

TEST_F(ScsDriverTest, TargetsOutsideTheLimitsAreClamped) {
  auto driver = Open();
  driver->SetJointTargets(Side::kLeft, Moved(*driver, Side::kLeft, 2, 10.0));
  for (int i = 0; i < 20; ++i) driver->Cycle();
  EXPECT_DOUBLE_EQ(driver->last_command(Side::kLeft)[2],
                   world_.platform().arm(Side::kLeft).upper_limits()[2]);
}

TEST_F(ScsDriverTest, WatchdogHoldsTheLastCommandWhenTargetsGoStale) {
  auto driver = Open();
  const Eigen::VectorXd target = Moved(*driver, Side::kLeft, 0, 60.0 * kDeg);
  driver->SetJointTargets(Side::kLeft, target);
  EXPECT_FALSE(driver->Cycle().stale);
  const Eigen::VectorXd after_one = driver->last_command(Side::kLeft);
  world_.Step(0.25);  // no new target for longer than stale_after_s (0.2 s)
  const CycleReport report = driver->Cycle();
  EXPECT_TRUE(report.stale);
  EXPECT_TRUE(driver->last_command(Side::kLeft).isApprox(after_one));
  driver->SetJointTargets(Side::kLeft, target);  // fresh again: moves on
  EXPECT_FALSE(driver->Cycle().stale);
  EXPECT_GT(driver->last_command(Side::kLeft)[0], after_one[0]);
}

TEST_F(ScsDriverTest, StopHoldsWhereTheArmsAre) {
  auto driver = Open();
  Track(driver.get(), Side::kLeft, Moved(*driver, Side::kLeft, 0, 0.5), 0.1);
  driver->Stop();
  const Eigen::VectorXd held = driver->JointPositions(Side::kLeft);
  Run(driver.get(), 0.5);
  EXPECT_LE((driver->JointPositions(Side::kLeft) - held).cwiseAbs().maxCoeff(), 0.03);
}

TEST_F(ScsDriverTest, AMissingServoAtStartNamesThePortAndTheServo) {
  SimServoBusConfig faults;
  faults.byte_time_s = 0.0;
  faults.silent_ids = {13};
  bus_->SetFaults(faults);
  try {
    Open();
    FAIL() << "expected a HardwareError";
  } catch (const HardwareError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("servo bus " + bus_->port_path()), std::string::npos) << what;
    EXPECT_NE(what.find("13 (left j3, timeout)"), std::string::npos) << what;
  }
}

TEST_F(ScsDriverTest, AMissingPortIsNamed) {
  servos_.port = "/dev/aerograsp-no-such-port";
  try {
    Open();
    FAIL() << "expected a HardwareError";
  } catch (const HardwareError& e) {
    EXPECT_NE(std::string(e.what()).find("servo bus: cannot open /dev/aerograsp-no-such-port"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ScsDriverTest, AServoFallingSilentKeepsItsLastPositionAndIsCounted) {
  auto driver = Open();
  Run(driver.get(), 0.05);
  const double before = driver->JointPositions(Side::kRight)[1];
  SimServoBusConfig faults;
  faults.byte_time_s = 0.0;
  faults.silent_ids = {22};
  bus_->SetFaults(faults);
  const CycleReport report = driver->Cycle();
  EXPECT_EQ(report.failed_reads, 1);
  EXPECT_EQ(driver->JointPositions(Side::kRight)[1], before);
  for (const ScsServoStatus& s : driver->servo_statuses())
    EXPECT_EQ(s.failed_reads, s.id == 22 ? 1 : 0) << s.name;
}

TEST_F(ScsDriverTest, CorruptedRepliesAreRejectedNotBelieved) {
  auto driver = Open();
  SimServoBusConfig faults;
  faults.byte_time_s = 0.0;
  faults.corrupt_probability = 0.02;
  faults.seed = 7;
  bus_->SetFaults(faults);
  const Eigen::VectorXd held = driver->last_command(Side::kLeft);
  Run(driver.get(), 0.2);
  EXPECT_GT(driver->counters().bad_checksums, 0);
  EXPECT_TRUE(CheckBusErrors(BusCounters{}, driver->counters(), DeviceHealthLimits{}));
  // Whatever got through is the truth: the arm holds still, readings stay on it.
  EXPECT_LE((driver->JointPositions(Side::kLeft) - held).cwiseAbs().maxCoeff(),
            2.0 * world_.arm(Side::kLeft).quantum_rad());
}

TEST_F(ScsDriverTest, ASlowServoTimesOut) {
  auto driver = Open();
  SimServoBusConfig faults;
  faults.byte_time_s = 0.0;
  faults.slow_ids = {14};
  faults.slow_extra_s = 0.5;  // beyond the 0.2 s reply timeout
  bus_->SetFaults(faults);
  const std::int64_t before = driver->counters().timeouts;
  EXPECT_GE(driver->Cycle().failed_reads, 1);
  EXPECT_GT(driver->counters().timeouts, before);
}

TEST_F(ScsDriverTest, ALateReplyIsSkippedAndNotCountedAsCorruption) {
  auto driver = Open();
  SimServoBusConfig faults;
  faults.byte_time_s = 0.0;
  faults.return_delay_s = 0.0;
  faults.slow_ids = {14};
  faults.slow_extra_s = 0.3;  // past the 0.2 s timeout: lands in the next servo's exchange
  bus_->SetFaults(faults);
  const BusCounters before = driver->counters();
  int late = 0;
  for (int i = 0; i < 3; ++i) {
    late += driver->Cycle().late_replies;
    bus_->SyncWithWorld();
    world_.Step(kCycle_s);
  }
  const BusCounters after = driver->counters();
  EXPECT_GT(late, 0);
  EXPECT_EQ(after.late_replies - before.late_replies, late);
  EXPECT_EQ(after.bad_checksums, before.bad_checksums);
  EXPECT_FALSE(CheckBusErrors(before, after, DeviceHealthLimits{}));
  // The late reply took nobody's place: only the slow servo missed its reads.
  for (const ScsServoStatus& s : driver->servo_statuses())
    EXPECT_EQ(s.failed_reads > 0, s.id == 14) << s.name;
}

TEST_F(ScsDriverTest, GripperClosesAndOpensThroughTheBus) {
  auto driver = Open();
  driver->SetGripper(Side::kLeft, GripperCommand::kClose);
  Run(driver.get(), 1.5);
  GripperState g = driver->Gripper(Side::kLeft);
  EXPECT_TRUE(g.closed);
  EXPECT_FALSE(g.holding);  // nothing between the fingers
  EXPECT_LT(g.aperture_m, 0.01);
  driver->SetGripper(Side::kLeft, GripperCommand::kOpen);
  Run(driver.get(), 1.5);
  g = driver->Gripper(Side::kLeft);
  EXPECT_FALSE(g.closed);
  EXPECT_NEAR(g.aperture_m, world_.platform().config().gripper.max_aperture_m, 0.005);
}

TEST_F(ScsDriverTest, TorqueOffLeavesTheServosLimp) {
  auto driver = Open();
  EXPECT_EQ(driver->SetTorque(false), BusStatus::kOk);
  Track(driver.get(), Side::kLeft, Moved(*driver, Side::kLeft, 0, 0.4), 0.3);
  EXPECT_EQ(bus_->Registers(11)[scs::reg::kTorqueEnable], 0);
  EXPECT_NEAR(world_.arm(Side::kLeft).q_true_rad()[0], world_.platform().home(Side::kLeft)[0],
              0.01);
}

TEST_F(ScsDriverTest, StatusRegistersArriveRoundRobin) {
  auto driver = Open();
  Run(driver.get(), 0.2);  // 20 cycles, 10 servos: each read twice
  for (const ScsServoStatus& s : driver->servo_statuses()) {
    EXPECT_NEAR(s.voltage_v, 7.4, 1e-9) << s.name;
    EXPECT_EQ(s.temperature_c, 35) << s.name;
  }
}

TEST_F(ScsDriverTest, TheDriversThreadRunsTheLoopOnItsOwn) {
  auto driver = Open();
  driver->StartThread();
  const BusCounters start = driver->counters();
  // Waits for the exchanges themselves, with a deadline far beyond their 0.1 s.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (driver->counters().exchanges < start.exchanges + 50 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  driver->StopThread();
  EXPECT_GE(driver->counters().exchanges, start.exchanges + 50);
}

}  // namespace
}  // namespace aerograsp
