#include <gtest/gtest.h>

#include <fstream>

#include "core/config.h"
#include "core/data_dir.h"
#include "hardware/hardware_config.h"
#include "hardware/hardware_factory.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/world.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {

/// A hardware YAML in the temp folder, next to copies of nothing: platform and
/// world point at the shipped files.
std::string WriteConfig(const std::string& name, const std::string& body) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << body;
  return path;
}

std::string ErrorOf(const std::string& path) {
  try {
    HardwareConfig::Load(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(HardwareConfigTest, ShippedFilesAreValid) {
  const HardwareConfig sim = HardwareConfig::Load(DataPath("config/hardware_sim.yaml"));
  EXPECT_EQ(sim.arms.backend, "sim-bus");
  EXPECT_EQ(sim.autopilot.backend, "sim-px4");
  EXPECT_TRUE(sim.NeedsWorld());
  const HardwareConfig real = HardwareConfig::Load(DataPath("config/hardware_example.yaml"));
  EXPECT_FALSE(real.NeedsWorld());
  ASSERT_TRUE(real.arms.servos_given);
  ASSERT_EQ(real.arms.scs.joints[1].size(), 4u);
  EXPECT_EQ(real.arms.scs.joints[1][2].id, 23);
  EXPECT_NEAR(real.arms.scs.joints[1][2].angle_at_max_rad, 205.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(real.arms.scs.grippers[0].id, 17);
  EXPECT_EQ(real.autopilot.px4.link, "serial");
}

TEST(HardwareConfigTest, BadValuesNameTheFileTheKeyAndTheBound) {
  std::string path = WriteConfig("hw_backend.yaml", "arms: {backend: usb}\n");
  EXPECT_NE(ErrorOf(path).find("hw_backend.yaml: arms.backend"), std::string::npos)
      << ErrorOf(path);
  path = WriteConfig("hw_rate.yaml", "autopilot: {setpoint_hz: 5}\n");
  EXPECT_NE(ErrorOf(path).find("hw_rate.yaml: autopilot.setpoint_hz: 5"), std::string::npos)
      << ErrorOf(path);
  path = WriteConfig("hw_key.yaml", "autopilot: {signing_key_hex: abc}\n");
  EXPECT_NE(ErrorOf(path).find("autopilot.signing_key_hex: must be 64 hex digits"),
            std::string::npos);
  path = WriteConfig("hw_baud.yaml", "arms: {baud: 1234}\n");
  EXPECT_NE(ErrorOf(path).find("arms.baud: 1234 is not a standard baud rate"), std::string::npos);
  path = WriteConfig("hw_replay.yaml", "camera: {backend: replay}\n");
  EXPECT_NE(ErrorOf(path).find("camera.path"), std::string::npos);
}

TEST(HardwareConfigTest, ServoIdsMustBeUniqueAndCalibrationsMustSpan) {
  const std::string servos =
      "arms:\n  servos:\n"
      "    left:\n      j1: {id: 11, deg_at_raw_0: -90, deg_at_raw_1023: 130}\n"
      "      gripper: {id: 17}\n"
      "    right:\n      j1: {id: 11, deg_at_raw_0: -90, deg_at_raw_1023: 130}\n"
      "      gripper: {id: 27}\n";
  std::string path = WriteConfig("hw_ids.yaml", servos);
  EXPECT_NE(ErrorOf(path).find("arms.servos.right.j1.id: 11 is used twice"), std::string::npos)
      << ErrorOf(path);
  path = WriteConfig("hw_span.yaml",
                     "arms:\n  servos:\n"
                     "    left:\n      j1: {id: 11, deg_at_raw_0: 10, deg_at_raw_1023: 10}\n"
                     "      gripper: {id: 17}\n"
                     "    right:\n      j1: {id: 21, deg_at_raw_0: -90, deg_at_raw_1023: 130}\n"
                     "      gripper: {id: 27}\n");
  EXPECT_NE(ErrorOf(path).find("arms.servos.left.j1: deg_at_raw_0 and deg_at_raw_1023 must differ"),
            std::string::npos)
      << ErrorOf(path);
}

TEST(HardwareConfigTest, UnknownKeysAreRejected) {
  const std::string path = WriteConfig("hw_typo.yaml", "arms: {prot: /dev/ttyUSB0}\n");
  EXPECT_NE(ErrorOf(path).find("prot"), std::string::npos) << ErrorOf(path);
}

TEST(HardwareFactoryTest, AMissingDeviceNamesItsPortBeforeAnythingMoves) {
  const std::string path = WriteConfig("hw_missing.yaml",
                                       "arms: {backend: scs, port: /dev/aerograsp-no-bus}\n"
                                       "autopilot: {backend: sim}\ncamera: {backend: sim}\n");
  try {
    Hardware::Open(HardwareConfig::Load(path), 1);
    FAIL() << "expected a HardwareError";
  } catch (const HardwareError& e) {
    EXPECT_EQ(std::string(e.what()),
              "servo bus: cannot open /dev/aerograsp-no-bus: No such file or directory");
  }
}

TEST(HardwareFactoryTest, TheSimulatedRunGoesThroughTheRealDrivers) {
  std::unique_ptr<Hardware> hw =
      Hardware::Open(HardwareConfig::Load(DataPath("config/hardware_sim.yaml")), 1);
  ASSERT_NE(hw->scs_arms(), nullptr);
  ASSERT_NE(hw->px4(), nullptr);
  ASSERT_NE(hw->world(), nullptr);
  Eigen::VectorXd target = hw->platform().home(Side::kLeft);
  target[0] += 0.3;
  for (int i = 0; i < 100; ++i) {
    hw->arms().SetJointTargets(Side::kLeft, target);
    hw->StepSimulation(0.01);
  }
  EXPECT_NEAR(hw->world()->arm(Side::kLeft).q_true_rad()[0], target[0], 0.01);
  EXPECT_NEAR(hw->arms().JointPositions(Side::kLeft)[0], target[0], 0.01);
  EXPECT_TRUE(hw->autopilot().State().link_ok);
  EXPECT_EQ(hw->autopilot().State().mode, FlightMode::kHold);  // the default world starts hovering
  EXPECT_TRUE(hw->autopilot().Hold().accepted);
}

TEST(HardwareConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  const HardwareConfig shipped = HardwareConfig::Load(DataPath("config/hardware_sim.yaml"));
  HardwareConfig c = shipped;
  c.autopilot.px4.setpoint_hz = 5.0;
  EXPECT_NE(testing::ValidationMessage(c, "h.yaml", "")
                .find("h.yaml: autopilot.setpoint_hz: 5 Hz is below the lower bound 10 Hz"),
            std::string::npos);
  EXPECT_NE(
      testing::ValidationMessage(c, "h.yaml", "hardware.")
          .find("h.yaml: hardware.autopilot.setpoint_hz: 5 Hz is below the lower bound 10 Hz"),
      std::string::npos);
  c = shipped;
  c.health.servo_max_failed_reads = 0;
  EXPECT_NE(
      testing::ValidationMessage(c, "h.yaml", "hardware.")
          .find("h.yaml: hardware.health.servo_max_failed_reads: 0 is below the lower bound 1"),
      std::string::npos);
  c = shipped;
  c.arms.scs.baud = 1234;
  EXPECT_NE(testing::ValidationMessage(c, "h.yaml", "hardware.")
                .find("h.yaml: hardware.arms.baud: 1234 is not a standard baud rate"),
            std::string::npos);
}

}  // namespace
}  // namespace aerograsp
