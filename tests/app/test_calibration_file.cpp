// The calibration file `calibrate` writes and the mission config that loads it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "app/calibration/calibration_file.h"
#include "app/runtime/mission_config.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class CalibrationFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           (std::string("aerograsp_calibration_") +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    calibration_.side = Side::kLeft;
    calibration_.method = "refined";
    calibration_.cMb =
        MakeTransform(Eigen::Vector3d(-0.15, 0.3, 0.1), Eigen::Vector3d(0.3, -0.2, 1.4));
    calibration_.dMb = MakeTransform(Eigen::Vector3d(0.0, -0.1525, 0.04), Eigen::Vector3d::Zero());
    calibration_.residual_mm = 0.4;
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// A mission config beside the calibration files, with `text` appended.
  std::string WriteMission(const std::string& text) const {
    const fs::path path = dir_ / "mission.yaml";
    std::ofstream(path) << "world: " << DataDir() << "/config/world_mission.yaml\n" << text;
    return path.string();
  }
  std::string MissionError(const std::string& text) const {
    try {
      MissionConfig::Load(WriteMission(text));
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
  ArmCalibration calibration_;
};

TEST_F(CalibrationFileTest, WrittenThenLoadedGivesTheSameTransforms) {
  const std::string path = (dir_ / "calibration_left.yaml").string();
  calibration_.Write(path);
  const ArmCalibration loaded = ArmCalibration::Load(path);
  EXPECT_EQ(loaded.side, Side::kLeft);
  EXPECT_EQ(loaded.method, "refined");
  EXPECT_TRUE(loaded.cMb.isApprox(calibration_.cMb, 1e-10));
  EXPECT_TRUE(loaded.dMb.isApprox(calibration_.dMb, 1e-10));
  EXPECT_DOUBLE_EQ(loaded.residual_mm, 0.4);
}

TEST_F(CalibrationFileTest, AMissionConfigLoadsItsArmsCalibrations) {
  calibration_.Write((dir_ / "calibration_left.yaml").string());
  const MissionConfig config =
      MissionConfig::Load(WriteMission("calibration_left: calibration_left.yaml\n"));
  EXPECT_EQ(config.calibration_left,
            (dir_ / "calibration_left.yaml").string());  // relative to the mission file
  ASSERT_TRUE(config.calibrated_cMb[0].has_value());
  EXPECT_TRUE(config.calibrated_cMb[0]->isApprox(calibration_.cMb, 1e-10));
  EXPECT_FALSE(config.calibrated_cMb[1].has_value());  // the right arm keeps its nominal mount
  // The shipped config names none.
  const MissionConfig shipped = MissionConfig::Load(DataPath("config/mission_default.yaml"));
  EXPECT_FALSE(shipped.calibrated_cMb[0].has_value() || shipped.calibrated_cMb[1].has_value());
}

TEST_F(CalibrationFileTest, BadCalibrationFilesAreNamedWithTheMissionField) {
  EXPECT_THAT(MissionError("calibration_right: nowhere.yaml\n"), HasSubstr("calibration_right"));
  EXPECT_THAT(MissionError("calibration_right: nowhere.yaml\n"), HasSubstr("nowhere.yaml"));

  std::ofstream(dir_ / "short.yaml") << "arm: left\ncMb: [1, 0, 0]\n";
  EXPECT_THAT(MissionError("calibration_left: short.yaml\n"),
              HasSubstr("calibration_left: " + (dir_ / "short.yaml").string() +
                        ": cMb: expected 16 numbers"));

  std::ofstream(dir_ / "broken.yaml") << "arm: left\ncMb: [1, 0, 0, 0,\n";  // not YAML
  EXPECT_THAT(MissionError("calibration_left: broken.yaml\n"), HasSubstr("broken.yaml"));

  std::ofstream(dir_ / "scaled.yaml")
      << "arm: left\ncMb: [2, 0, 0, 0.1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n";
  EXPECT_THAT(MissionError("calibration_left: scaled.yaml\n"),
              HasSubstr("cMb: not a rigid transform"));

  calibration_.side = Side::kRight;
  calibration_.Write((dir_ / "calibration_right.yaml").string());
  EXPECT_THAT(MissionError("calibration_left: calibration_right.yaml\n"),
              HasSubstr("calibrates the right arm, not the left one"));
}

/// The numbers after `key="` (URDF attributes) or after `--key ` (ROS 2 arguments).
std::vector<double> Numbers(const std::string& text, const std::string& pattern) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(text, m, std::regex(pattern))) << pattern << " in " << text;
  std::vector<double> v;
  for (std::size_t i = 1; i < m.size(); ++i) v.push_back(std::stod(m[i].str()));
  return v;
}

TEST(RosFramesTest, UrdfRpyAndTfQuaternionReproduceTheMatrix) {
  FastRandom rng(5);
  std::vector<Eigen::Isometry3d> transforms = {
      // Pitch at +-90 deg (URDF's rpy singularity) and a half turn.
      MakeTransform(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.4, M_PI / 2, -0.2)),
      MakeTransform(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.0, -M_PI / 2, 1.0)),
      MakeTransform(Eigen::Vector3d(-0.05, 0.0, 0.4), Eigen::Vector3d(M_PI, 0.0, 0.0))};
  for (int i = 0; i < 20; ++i) {
    transforms.push_back(MakeTransform(
        Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)),
        Eigen::Vector3d(rng.Uniform(-3.1, 3.1), rng.Uniform(-1.5, 1.5), rng.Uniform(-3.1, 3.1))));
  }
  const std::string num = "([-+0-9.eE]+)";
  for (const Eigen::Isometry3d& cMb : transforms) {
    const std::string urdf = UrdfFixedJoint("j", "camera_optical", "arm_left_mount", cMb);
    EXPECT_THAT(urdf, HasSubstr("<parent link=\"camera_optical\"/>"));
    EXPECT_THAT(urdf, HasSubstr("<child link=\"arm_left_mount\"/>"));
    const std::vector<double> xyz = Numbers(urdf, "xyz=\"" + num + " " + num + " " + num + "\"");
    const std::vector<double> rpy = Numbers(urdf, "rpy=\"" + num + " " + num + " " + num + "\"");
    const Eigen::Isometry3d from_urdf = MakeTransform(Eigen::Vector3d(xyz[0], xyz[1], xyz[2]),
                                                      Eigen::Vector3d(rpy[0], rpy[1], rpy[2]));
    EXPECT_TRUE(from_urdf.isApprox(cMb, 1e-12)) << urdf;

    const std::string tf = StaticTransformPublisherArgs("camera_optical", "arm_left_mount", cMb);
    EXPECT_THAT(tf, HasSubstr("--frame-id camera_optical --child-frame-id arm_left_mount"));
    const std::vector<double> t =
        Numbers(tf, "--x " + num + " --y " + num + " --z " + num + " --qx " + num + " --qy " + num +
                        " --qz " + num + " --qw " + num);
    const Eigen::Isometry3d from_tf = MakeTransformWxyz(Eigen::Vector3d(t[0], t[1], t[2]),
                                                        Eigen::Vector4d(t[6], t[3], t[4], t[5]));
    EXPECT_TRUE(from_tf.isApprox(cMb, 1e-12)) << tf;
  }
}

TEST(PlatformWithArmBaseTest, MovesOneArmsBaseAndRefusesANonRigidOne) {
  const Platform nominal = Platform::Load(DataPath("config/platform_4dof.yaml"));
  const Eigen::Isometry3d dMb =
      nominal.dMb(Side::kLeft) *
      MakeTransform(Eigen::Vector3d(0.002, -0.001, 0.003), Eigen::Vector3d(0.01, 0.0, -0.02));
  const Platform calibrated = nominal.WithArmBase(Side::kLeft, dMb);
  EXPECT_TRUE(calibrated.dMb(Side::kLeft).isApprox(dMb, 1e-12));
  EXPECT_TRUE(calibrated.dMb(Side::kRight).isApprox(nominal.dMb(Side::kRight), 1e-12));
  EXPECT_TRUE(calibrated.dMc().isApprox(nominal.dMc(), 1e-12));
  Eigen::Isometry3d sheared = dMb;
  sheared.linear()(0, 1) = 0.3;
  EXPECT_THROW(nominal.WithArmBase(Side::kLeft, sheared), std::invalid_argument);
}

}  // namespace
}  // namespace aerograsp
