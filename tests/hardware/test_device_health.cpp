// The device health checks (hardware/device_health.h): each bound fires just
// past its value and not before, each fault of a device is reported once, and
// the limits refuse bad values with the key named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/config.h"
#include "hardware/device_health.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

ScsServoStatus Servo(int id = 12) {
  ScsServoStatus s;
  s.id = id;
  s.name = "left j2";
  s.raw_position = 500;
  s.voltage_v = 7.4;
  s.temperature_c = 35;
  return s;
}

std::vector<DeviceFaultKind> Kinds(const std::vector<DeviceFault>& faults) {
  std::vector<DeviceFaultKind> kinds;
  for (const DeviceFault& f : faults) kinds.push_back(f.kind);
  return kinds;
}

TEST(DeviceHealthTest, HealthyServoHasNoFault) {
  EXPECT_TRUE(CheckServo(Servo(), 0.01, DeviceHealthLimits{}).empty());
}

TEST(DeviceHealthTest, ServoSilentFromMaxFailedReads) {
  const DeviceHealthLimits limits;  // 3
  ScsServoStatus s = Servo();
  s.failed_reads = 2;
  EXPECT_TRUE(CheckServo(s, 0.0, limits).empty());
  s.failed_reads = 3;
  const std::vector<DeviceFault> faults = CheckServo(s, 0.0, limits);
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, DeviceFaultKind::kServoSilent);
  EXPECT_EQ(faults[0].Text(), "servo left j2 (id 12): 3 reads failed in a row (at most 2)");
}

TEST(DeviceHealthTest, StaleReadingPastItsAge) {
  const DeviceHealthLimits limits;  // 0.05 s
  EXPECT_TRUE(CheckServo(Servo(), 0.05, limits).empty());
  EXPECT_EQ(Kinds(CheckServo(Servo(), 0.051, limits)),
            std::vector<DeviceFaultKind>{DeviceFaultKind::kServoStale});
}

TEST(DeviceHealthTest, VoltageAndTemperatureOutOfRange) {
  const DeviceHealthLimits limits;  // 6.0-8.4 V, 70 C
  ScsServoStatus s = Servo();
  s.voltage_v = 5.9;
  s.temperature_c = 71;
  const std::vector<DeviceFault> faults = CheckServo(s, 0.0, limits);
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_EQ(faults[0].Text(), "servo left j2 (id 12): supply 5.9 V outside 6.0-8.4 V");
  EXPECT_EQ(faults[1].Text(), "servo left j2 (id 12): 71 C, above 70 C");
  s.voltage_v = 0.0;  // not read yet: nothing to judge
  s.temperature_c = 70;
  EXPECT_TRUE(CheckServo(s, 0.0, limits).empty());
}

TEST(DeviceHealthTest, BusErrorRateAboveItsBound) {
  DeviceHealthLimits limits;  // 5 %, from 20 exchanges
  BusCounters from, to;
  to.exchanges = 100;
  to.bad_checksums = 5;
  EXPECT_FALSE(CheckBusErrors(from, to, limits));  // 5 %: at the bound
  to.bad_checksums = 6;
  const auto fault = CheckBusErrors(from, to, limits);
  ASSERT_TRUE(fault);
  EXPECT_EQ(fault->kind, DeviceFaultKind::kBusCorrupt);
  EXPECT_THAT(fault->Text(), HasSubstr("servo bus: 6 of the last 100 replies corrupted (6.0 %"));
  to.exchanges = 19;  // too few to judge
  EXPECT_FALSE(CheckBusErrors(from, to, limits));
}

TEST(DeviceHealthTest, LateRepliesAreNotCorruption) {
  DeviceHealthLimits limits;
  BusCounters from, to;
  to.exchanges = 100;
  to.timeouts = 50;
  to.late_replies = 50;  // each a timeout of its own exchange already
  EXPECT_FALSE(CheckBusErrors(from, to, limits));
}

TEST(DeviceHealthTest, LinkLostByFlagOrByStateAge) {
  const DeviceHealthLimits limits;  // 0.1 s
  VehicleState state;
  EXPECT_FALSE(CheckAutopilotLink(state, 0.1, limits));
  EXPECT_EQ(CheckAutopilotLink(state, 0.11, limits)->kind, DeviceFaultKind::kLinkLost);
  state.link_ok = false;
  EXPECT_EQ(CheckAutopilotLink(state, 0.0, limits)->Text(),
            "autopilot: the link is lost (no heartbeat)");
}

TEST(DeviceHealthTest, RefusalIsAFaultOnlyInTheAir) {
  const CommandAck refused{false, "temporarily rejected"};
  EXPECT_FALSE(CheckCommandAnswer("take-off", refused, FlightMode::kDisarmed));
  EXPECT_FALSE(CheckCommandAnswer("take-off", refused, FlightMode::kLanded));
  EXPECT_FALSE(CheckCommandAnswer("land", CommandAck{true, ""}, FlightMode::kHold));
  const auto fault = CheckCommandAnswer("land", refused, FlightMode::kHold);
  ASSERT_TRUE(fault);
  EXPECT_EQ(fault->Text(), "autopilot: refused land: temporarily rejected");
}

TEST(DeviceHealthTest, CameraWithoutNewFramesOrDepth) {
  const DeviceHealthLimits limits;  // 0.07 s, 0.05 s
  EXPECT_TRUE(CheckCamera(0.07, -1.0, limits).empty());
  EXPECT_TRUE(CheckCamera(0.0, 0.049, limits).empty());
  EXPECT_EQ(Kinds(CheckCamera(0.071, 0.05, limits)),
            (std::vector<DeviceFaultKind>{DeviceFaultKind::kCameraNoFrame,
                                          DeviceFaultKind::kCameraBadDepth}));
}

TEST(DeviceHealthTest, DepthHasDataFindsOnePixel) {
  DepthImage depth(8, 6, 0);
  EXPECT_FALSE(DepthHasData(depth));
  depth.at(7, 5) = 1;
  EXPECT_TRUE(DepthHasData(depth));
}

TEST(DeviceHealthTest, MonitorAgesReadingsByTheirChangesAndReportsOnce) {
  DeviceHealth health{DeviceHealthLimits{}};
  ScsServoStatus s = Servo();
  BusCounters counters;
  for (int k = 0; k <= 5; ++k) {  // a good read every 10 ms
    s.good_reads = k;
    counters.exchanges += 12;
    EXPECT_TRUE(health.Servos(0.01 * k, {s}, counters).empty()) << k;
  }
  // No good read from 0.05 s on: stale past 0.10 s, reported once.
  EXPECT_TRUE(health.Servos(0.10, {s}, counters).empty());
  const std::vector<DeviceFault> faults = health.Servos(0.11, {s}, counters);
  EXPECT_EQ(Kinds(faults), std::vector<DeviceFaultKind>{DeviceFaultKind::kServoStale});
  EXPECT_TRUE(health.Servos(0.20, {s}, counters).empty());
  EXPECT_EQ(health.counts().at("servo_stale"), 1);
}

TEST(DeviceHealthTest, MonitorAgesTheVehicleStateByItsStamp) {
  DeviceHealth health{DeviceHealthLimits{}};
  VehicleState state;
  for (int k = 0; k < 10; ++k) {
    state.stamp_s = 0.02 * k;
    EXPECT_TRUE(health.Autopilot(0.02 * k, state).empty());
  }
  EXPECT_TRUE(health.Autopilot(0.275, state).empty());  // 0.095 s since the last new state
  EXPECT_EQ(health.Autopilot(0.285, state).size(), 1u);
}

TEST(DeviceHealthTest, MonitorRestartsTheFrameAgeAfterIdle) {
  DeviceHealth health{DeviceHealthLimits{}};
  EXPECT_TRUE(health.Frame(1.0, 1.0, true).empty());
  health.CameraIdle();  // no frames wanted for a while
  EXPECT_TRUE(health.Frame(5.0, 5.0, true).empty());
  EXPECT_TRUE(health.Frame(5.033, 5.0, true).empty());  // the same frame again
  EXPECT_TRUE(health.Frame(5.067, 5.0, true).empty());
  const std::vector<DeviceFault> faults = health.Frame(5.1, 5.0, true);
  EXPECT_EQ(Kinds(faults), std::vector<DeviceFaultKind>{DeviceFaultKind::kCameraNoFrame});
}

TEST(DeviceHealthTest, LimitsRefuseBadValuesByKey) {
  DeviceHealthLimits limits;
  EXPECT_NO_THROW(limits.Validate("hw.yaml", "health."));
  limits.servo_max_failed_reads = 0;
  try {
    limits.Validate("hw.yaml", "health.");
    FAIL() << "accepted 0 failed reads";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("hw.yaml: health.servo_max_failed_reads"));
  }
  limits = {};
  limits.servo_max_voltage_v = 5.0;  // below the minimum
  EXPECT_THROW(limits.Validate("hw.yaml", "health."), ConfigError);
}

}  // namespace
}  // namespace aerograsp
