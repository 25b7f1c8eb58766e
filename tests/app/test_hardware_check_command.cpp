#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include "app/commands/hardware_check_command.h"
#include "core/data_dir.h"

namespace aerograsp {
namespace {

TEST(HardwareCheckCommandTest, EverySimulatedDeviceAnswers) {
  HardwareCheckOptions options;
  options.config_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out;
  EXPECT_EQ(RunHardwareCheck(options, out), 0) << out.str();
  EXPECT_NE(out.str().find("10 servos answer"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("result: every device answers"), std::string::npos) << out.str();
}

TEST(HardwareCheckCommandTest, AMissingDeviceIsNamedWithItsPort) {
  const std::string path = ::testing::TempDir() + "/hw_check_missing.yaml";
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms: {backend: scs, port: /dev/aerograsp-no-bus}\n"
                      << "autopilot: {backend: sim}\ncamera: {backend: sim}\n";
  HardwareCheckOptions options;
  options.config_path = path;
  std::ostringstream out;
  EXPECT_EQ(RunHardwareCheck(options, out), 1);
  EXPECT_NE(out.str().find("arms       FAILED: servo bus: cannot open /dev/aerograsp-no-bus"),
            std::string::npos)
      << out.str();
}

TEST(HardwareCheckCommandTest, APortThatIsARegularFileIsRefusedAndLeftUntouched) {
  const std::string port = ::testing::TempDir() + "/hw_check_not_a_port.txt";
  std::ofstream(port) << "notes\n";
  const std::string path = ::testing::TempDir() + "/hw_check_file_port.yaml";
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms: {backend: scs, port: " << port << "}\n"
                      << "autopilot: {backend: sim}\ncamera: {backend: sim}\n";
  HardwareCheckOptions options;
  options.config_path = path;
  std::ostringstream out;
  EXPECT_EQ(RunHardwareCheck(options, out), 1);
  EXPECT_NE(out.str().find("servo bus: " + port + " is a regular file, not a serial port"),
            std::string::npos)
      << out.str();
  std::ifstream in(port, std::ios::binary);
  const std::string contents((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  EXPECT_EQ(contents, "notes\n");
}

TEST(HardwareCheckCommandTest, APortThatIsAFolderIsRefusedByName) {
  const std::string path = ::testing::TempDir() + "/hw_check_folder_port.yaml";
  std::ofstream(path) << "platform: " << DataPath("config/platform_4dof.yaml") << "\n"
                      << "world: " << DataPath("config/world_default.yaml") << "\n"
                      << "arms: {backend: scs, port: /tmp}\n"
                      << "autopilot: {backend: sim}\ncamera: {backend: sim}\n";
  HardwareCheckOptions options;
  options.config_path = path;
  std::ostringstream out;
  EXPECT_EQ(RunHardwareCheck(options, out), 1);
  EXPECT_NE(out.str().find("servo bus: /tmp is a folder, not a serial port"), std::string::npos)
      << out.str();
}

}  // namespace
}  // namespace aerograsp
