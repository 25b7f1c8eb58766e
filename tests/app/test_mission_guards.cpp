// The mission's guards seen firing: each device fault the simulated devices
// can produce, a lost link, a refused command, a refused take-off and the
// safe-volume interlock on the measured joints. Each mission runs a few
// simulated seconds with one fault from a fixed time; the checks are the
// cause the mission names, the count in the result, one log line per fault and
// the arms stopped within 0.1 s of the fault showing (all on the simulated clock).
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "app/runtime/mission_record.h"
#include "app/runtime/mission_runner.h"
#include "core/data_dir.h"
#include "hardware/hardware_config.h"

namespace aerograsp {
namespace {

struct Flown {
  MissionResult result;
  MissionRecord record;
  std::string log;
  /// When the arms machine entered its emergency stop; < 0: never.
  double arms_stopped_s() const {
    for (const MissionTransition& t : record.transitions) {
      if (t.machine == "arms" && t.to == "emergency stop") return t.t_s;
    }
    return -1.0;
  }
  int Count(const std::string& text) const {
    int n = 0;
    for (std::size_t at = log.find(text); at != std::string::npos; at = log.find(text, at + 1)) ++n;
    return n;
  }
};

/// `drivers`: the real SCS and PX4 drivers against the simulated bus and PX4
/// (data/config/hardware_sim.yaml); else every device in process.
Flown Fly(bool drivers, double timeout_s, const std::function<void(HardwareConfig*)>& faults) {
  MissionOptions options;
  options.seed = 1;
  options.timeout_s = timeout_s;
  if (drivers) options.hardware_path = DataPath("config/hardware_sim.yaml");
  options.adjust_hardware = faults;
  Flown flown;
  std::ostringstream log;
  flown.result = RunMission(options, &flown.record, &log);
  flown.log = log.str();
  return flown;
}

/// The arms stopped within 0.1 s of the first faulty act of a simulated device.
void ExpectStoppedSoonAfterTheFault(const Flown& flown) {
  ASSERT_GE(flown.result.simulated_fault_s, 0.0) << flown.log;
  const double stopped = flown.arms_stopped_s();
  ASSERT_GE(stopped, 0.0) << flown.log;
  EXPECT_GE(stopped, flown.result.simulated_fault_s);
  EXPECT_LE(stopped, flown.result.simulated_fault_s + 0.1) << flown.log;
  EXPECT_EQ(flown.result.emergency_stops, 1);
  EXPECT_FALSE(flown.result.success);
}

TEST(MissionGuardsTest, SilentServoStopsTheArmsAndIsLoggedOnce) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->arms.sim_bus.silent_ids = {12};
    hw->arms.sim_bus.faults_from_s = 4.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.failure, "servo left j2 (id 12): 3 reads failed in a row (at most 2)");
  EXPECT_EQ(flown.result.device_faults.at("servo_silent"), 1);
  EXPECT_EQ(flown.Count("device fault: servo left j2 (id 12): 3 reads failed"), 1) << flown.log;
}

TEST(MissionGuardsTest, CorruptedBusStopsTheArms) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->arms.sim_bus.corrupt_probability = 0.05;
    hw->arms.sim_bus.faults_from_s = 4.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.count("bus_corrupt"), 1u) << flown.log;
  EXPECT_EQ(flown.Count("device fault: servo bus: "), 1) << flown.log;
}

TEST(MissionGuardsTest, HotAndUnderVoltageServosEachLoggedOnce) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->arms.sim_bus.hot_ids = {21};
    hw->arms.sim_bus.low_voltage_ids = {14};
    hw->arms.sim_bus.faults_from_s = 4.0;
  });
  // The status registers are read round robin, one servo a cycle: the faults
  // show within one round of the ten servos.
  const double stopped = flown.arms_stopped_s();
  ASSERT_GE(stopped, 4.0) << flown.log;
  EXPECT_LE(stopped, 4.0 + 0.11 + 0.01) << flown.log;
  EXPECT_EQ(flown.Count("device fault: servo right j1 (id 21): 85 C, above 70 C"), 1) << flown.log;
  EXPECT_EQ(flown.Count("device fault: servo left j4 (id 14): supply 5.0 V outside 6.0-8.4 V"), 1)
      << flown.log;
  EXPECT_EQ(flown.result.device_faults.at("servo_temperature"), 1);
  EXPECT_EQ(flown.result.device_faults.at("servo_voltage"), 1);
}

TEST(MissionGuardsTest, LostLinkStopsTheArmsAndHoldsOnce) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->autopilot.sim_px4.silent = true;
    hw->autopilot.sim_px4.faults_from_s = 4.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.at("link_lost"), 1);
  EXPECT_NE(flown.result.failure.find("autopilot: the newest vehicle state is"), std::string::npos)
      << flown.result.failure;
  // The hold goes unanswered; it is tried once, not every cycle.
  EXPECT_EQ(flown.Count("autopilot refused hold"), 1) << flown.log;
}

TEST(MissionGuardsTest, TwoFaultsAtOnceStopTheArmsOnceAndHoldTheVehicleOnce) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->arms.sim_bus.silent_ids = {12};
    hw->arms.sim_bus.faults_from_s = 4.0;
    hw->autopilot.sim_px4.silent = true;
    hw->autopilot.sim_px4.faults_from_s = 4.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.count("servo_silent"), 1u) << flown.log;
  EXPECT_EQ(flown.result.device_faults.count("link_lost"), 1u) << flown.log;
  // The hold goes unanswered; a second cause does not send it again.
  EXPECT_EQ(flown.Count("autopilot refused hold"), 1) << flown.log;
}

TEST(MissionGuardsTest, CommandRefusedInFlightStopsTheArms) {
  // Armed and taking off before the fault; the switch to offboard for the
  // approach is the first command it refuses.
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->autopilot.sim_px4.reject_commands = true;
    hw->autopilot.sim_px4.faults_from_s = 1.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.at("command_rejected"), 1);
  EXPECT_EQ(flown.Count("device fault: autopilot: refused the position setpoint"), 1) << flown.log;
}

TEST(MissionGuardsTest, RefusedTakeOffEndsTheMissionOnTheGround) {
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->autopilot.sim_px4.reject_commands = true;
    hw->autopilot.sim_px4.faults_from_s = 0.0;
  });
  EXPECT_FALSE(flown.result.success);
  EXPECT_NE(flown.result.failure.find("the autopilot refused to take off"), std::string::npos)
      << flown.result.failure;
  // On the ground a refusal is an answer, not a device fault: nothing flies.
  EXPECT_TRUE(flown.result.device_faults.empty());
  EXPECT_LT(flown.result.sim_time_s, 2.0);
  EXPECT_EQ(flown.Count("vehicle idle -> take-off"), 0) << flown.log;
}

TEST(MissionGuardsTest, FrozenCameraStopsTheArms) {
  const Flown flown = Fly(false, 8.0, [](HardwareConfig* hw) {
    hw->camera.sim.frozen = true;
    hw->camera.sim.faults_from_s = 5.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.at("camera_no_frame"), 1);
  EXPECT_EQ(flown.Count("device fault: camera: no new frame for"), 1) << flown.log;
}

TEST(MissionGuardsTest, CameraWithoutDepthStopsTheArms) {
  const Flown flown = Fly(false, 8.0, [](HardwareConfig* hw) {
    hw->camera.sim.no_depth = true;
    hw->camera.sim.faults_from_s = 5.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.device_faults.at("camera_bad_depth"), 1);
  EXPECT_EQ(flown.Count("device fault: camera: no valid depth pixel for"), 1) << flown.log;
}

TEST(MissionGuardsTest, SafeVolumeInterlockActsOnTheMeasuredJoints) {
  // The left j2 servo's sensor is 60 deg off: by its reading the arm is inside
  // the safe volume, where it truly is not. A wrong reading is only seen by
  // where it says the arm is; the stop holds the arm at that reading, which
  // for the servo (its control loop uses the same sensor) is where it is.
  const Flown flown = Fly(true, 8.0, [](HardwareConfig* hw) {
    hw->arms.sim_bus.offset_ids = {12};
    hw->arms.sim_bus.offset_deg = 60.0;
    hw->arms.sim_bus.faults_from_s = 4.0;
  });
  ExpectStoppedSoonAfterTheFault(flown);
  EXPECT_EQ(flown.result.failure, "left arm entered the safe volume");
  EXPECT_TRUE(flown.result.device_faults.empty());
}

TEST(MissionGuardsTest, HealthyDevicesRaiseNoFault) {
  const Flown flown = Fly(true, 6.0, {});
  EXPECT_TRUE(flown.result.device_faults.empty()) << flown.log;
  EXPECT_LT(flown.result.simulated_fault_s, 0.0);
  EXPECT_EQ(flown.result.failure, "the mission took longer than 6 s");
}

}  // namespace
}  // namespace aerograsp
