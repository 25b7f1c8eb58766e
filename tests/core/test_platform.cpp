#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/camera_model.h"
#include "core/config.h"
#include "core/platform.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

std::string Config(const std::string& name) {
  return std::string(AEROGRASP_DATA_DIR) + "/config/" + name;
}

TEST(PlatformTest, DefaultGripperConfigIsValid) {
  PlatformConfig c = PlatformConfig::Load(Config("platform_4dof.yaml"));
  c.gripper = GripperConfig{};
  EXPECT_NO_THROW(c.Validate(c.source, ""));
}

class ShippedPlatformTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedPlatformTest, LoadsWithArmsAtTheirMounts) {
  const Platform p = Platform::Load(Config(GetParam()));
  EXPECT_TRUE(p.dMb(Side::kLeft).translation().isApprox(Eigen::Vector3d(0, -0.1525, 0.04)));
  EXPECT_TRUE(p.dMb(Side::kRight).translation().isApprox(Eigen::Vector3d(0, 0.1525, 0.04)));
  EXPECT_EQ(p.arm(Side::kLeft).dof(), p.arm(Side::kRight).dof());
  EXPECT_TRUE(p.arm(Side::kLeft).WithinLimits(p.home(Side::kLeft)));
  EXPECT_EQ(p.camera().width, 640);
  EXPECT_DOUBLE_EQ(p.camera().fx, 615.0);
  ASSERT_EQ(p.safe_volume_d().size(), 1u);
}

TEST_P(ShippedPlatformTest, CameraLooksForwardAndDownAtTheArmsWorkspace) {
  const Platform p = Platform::Load(Config(GetParam()));
  const Eigen::Vector3d view_d = p.dMc().linear().col(2);
  EXPECT_GT(view_d.x(), 0.3);  // forward
  EXPECT_GT(view_d.z(), 0.8);  // and mostly down (FRD)
  // The region the arms grasp from above (midway between them, 0.075 m ahead
  // and 0.47 m below the body; data/config/mission_default.yaml) and a box of
  // +-5 cm around it (the hover sway, the object's size) are in the image.
  for (double dx : {-0.05, 0.0, 0.05}) {
    for (double dz : {-0.05, 0.0, 0.05}) {
      const Eigen::Vector3d p_c = p.dMc().inverse() * Eigen::Vector3d(0.075 + dx, 0.0, 0.47 + dz);
      ASSERT_GT(p_c.z(), 0.0);
      const Eigen::Vector2d uv = p.camera().Project(p_c);
      EXPECT_GT(uv.x(), 0);
      EXPECT_LT(uv.x(), 640);
      EXPECT_GT(uv.y(), 0) << dx << " " << dz;
      EXPECT_LT(uv.y(), 480) << dx << " " << dz;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Configs, ShippedPlatformTest,
                         ::testing::Values("platform_4dof.yaml", "platform_6dof.yaml"));

// Unique per test process (ctest may run cases in parallel); beside data/config.
std::string MutatedPath() {
  return Config(".test_platform_" + std::to_string(::getpid()) + ".yaml");
}

// Writes a copy of the 4-DoF config with one text substitution into a temporary folder
// beside data/config so its relative paths still resolve.
std::string MutatedConfig(const std::string& from, const std::string& to) {
  std::ifstream in(Config("platform_4dof.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string original = text.str();
  const std::size_t at = original.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string mutated = original;
  mutated.replace(at, from.size(), to);
  const std::string path = MutatedPath();
  std::ofstream(path) << mutated;
  return path;
}

struct BadConfigCase {
  std::string name;     // test name
  std::string from;     // text of the shipped config to replace
  std::string to;       // what replaces it
  std::string key;      // the key the message must name, after the file
  std::string message;  // what the message must say about it
};

void PrintTo(const BadConfigCase& c, std::ostream* os) { *os << c.name; }

class BadPlatformConfigTest : public ::testing::TestWithParam<BadConfigCase> {
 protected:
  void TearDown() override { std::filesystem::remove(MutatedPath()); }
};

TEST_P(BadPlatformConfigTest, FailsNamingFileKeyAndProblem) {
  const BadConfigCase& c = GetParam();
  const std::string path = MutatedConfig(c.from, c.to);
  try {
    Platform::Load(path);
    FAIL() << "expected an error containing: " << c.message;
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ": " + c.key + ": "));
    EXPECT_THAT(e.what(), HasSubstr(c.message));
  }
}

const char* kHome = "home_rad: [0.0, -0.6283185, 2.0943951, 0.0]   #";

INSTANTIATE_TEST_SUITE_P(
    Cases, BadPlatformConfigTest,
    ::testing::Values(
        BadConfigCase{"ArmTypeUnknown", "arm_type: 4dof", "arm_type: 5dof", "arm_type",
                      "'5dof' is not one of: 4dof, 6dof"},
        BadConfigCase{"ArmTypeDisagreesWithUrdf", "arm_type: 4dof", "arm_type: 6dof",
                      "arms.left.urdf", "has 4 moving joints but arm_type is 6dof"},
        BadConfigCase{"ApertureTooLarge", "max_aperture_m: 0.12", "max_aperture_m: 0.5",
                      "gripper.max_aperture_m", "0.5 m is above the upper bound 0.3 m"},
        BadConfigCase{"CloseTimeNegative", "close_time_s: 0.8", "close_time_s: -1",
                      "gripper.close_time_s", "-1 s is below the lower bound 0.001 s"},
        BadConfigCase{"MassNotANumber", "mass_kg: 3.75", "mass_kg: fast", "vehicle.mass_kg",
                      "expected a number, got 'fast'"},
        BadConfigCase{"HomeBeyondLimit", kHome, "home_rad: [0.0, -0.6283185, 2.9, 0.0]   #",
                      "arms.left.home_rad[2]", "2.9 rad is above the upper bound 2.61799 rad"},
        BadConfigCase{"HomeWrongSize", kHome, "home_rad: [0.0]   #", "arms.left.home_rad",
                      "expected 4 values, got 1"},
        BadConfigCase{"MountLinkMissing", "mount_link: arm_left_mount", "mount_link: arm_lft_mount",
                      "arms.left.mount_link", "no link named 'arm_lft_mount'"},
        BadConfigCase{"ArmUrdfMissing", "urdf: ../robots/arm4.urdf", "urdf: ../robots/nope.urdf",
                      "arms.left.urdf", "nope.urdf' does not exist"},
        BadConfigCase{"UnknownTopLevelKey", "gripper:", "griper:", "griper",
                      "unknown key (expected one of: arm_type, vehicle, camera, arms, gripper)"},
        BadConfigCase{"CameraXmlNotACamera", "xml: ../camera/d435_color_640x480.xml",
                      "xml: ../robots/vehicle.urdf", "camera.xml", "no camera named 'd435_color'"}),
    [](const ::testing::TestParamInfo<BadConfigCase>& info) { return info.param.name; });

TEST(PlatformConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  PlatformConfig c = PlatformConfig::Load(Config("platform_4dof.yaml"));
  c.vehicle_mass_kg = 60.0;
  EXPECT_THAT(testing::ValidationMessage(c, "p.yaml", ""),
              HasSubstr("p.yaml: vehicle.mass_kg: 60 kg is above the upper bound 50 kg"));
  EXPECT_THAT(testing::ValidationMessage(c, "p.yaml", "platform."),
              HasSubstr("p.yaml: platform.vehicle.mass_kg: 60 kg is above the upper bound 50 kg"));
  c = PlatformConfig::Load(Config("platform_4dof.yaml"));
  c.gripper.finger_clearance_m = 0.04;
  c.gripper.max_aperture_m = 0.05;
  EXPECT_THAT(testing::ValidationMessage(c, "p.yaml", "platform."),
              HasSubstr("p.yaml: platform.gripper.finger_clearance_m: twice the clearance"));
}

TEST(CameraIntrinsicsTest, ValidateNamesTheFileAndTheFullKeyPath) {
  CameraIntrinsics K;
  K.cx = 700.0;  // right of the 640 px wide image
  EXPECT_THAT(testing::ValidationMessage(K, "cam.yaml", ""),
              HasSubstr("cam.yaml: cx: 700 px is above the upper bound 640 px"));
  EXPECT_THAT(testing::ValidationMessage(K, "cam.yaml", "intrinsics."),
              HasSubstr("cam.yaml: intrinsics.cx: 700 px is above the upper bound 640 px"));
  K = CameraIntrinsics{};
  K.fy = 0.0;
  EXPECT_THAT(testing::ValidationMessage(K, "cam.yaml", "intrinsics."),
              HasSubstr("cam.yaml: intrinsics.fy: 0 px must be positive"));
}

}  // namespace
}  // namespace aerograsp
