#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/calibration/calibrate_command.h"
#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_visp.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "core/transforms.h"
#include "hardware/sim/world.h"
#include "tests/common/earlier_report.h"
#include "tests/common/output_folder_test.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class CalibrateCommandTest : public testing::OutputFolderTest {
 protected:
  CalibrateCommandTest() : OutputFolderTest("aerograsp_calibrate_") {}
  void TearDown() override {
    OutputFolderTest::TearDown();
    fs::remove_all(inputs());
  }
  /// The test's input files, beside its report folder.
  std::string inputs() const { return folder_ + ".in"; }

  /// data/config/hardware_sim.yaml in inputs() (its paths made absolute) with
  /// each `replace` pair applied to its text.
  std::string SimHardware(const std::vector<std::pair<std::string, std::string>>& replace) {
    std::ifstream in(DataPath("config/hardware_sim.yaml"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto sub = [&text](const std::string& from, const std::string& to) {
      const std::size_t at = text.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      text.replace(at, from.size(), to);
    };
    sub("platform: platform_4dof.yaml", "platform: " + DataPath("config/platform_4dof.yaml"));
    sub("world: world_default.yaml", "world: " + DataPath("config/world_default.yaml"));
    for (const auto& [from, to] : replace) sub(from, to);
    fs::create_directories(inputs());
    const std::string path = (fs::path(inputs()) / "hw.yaml").string();
    std::ofstream(path) << text;
    return path;
  }

  /// The message of what `options` throws ("no error" when it succeeds).
  std::string ErrorOf(const CalibrateCommandOptions& options, std::ostringstream* out,
                      const std::string& answer = "") {
    std::istringstream in(answer);
    std::ostringstream progress;
    try {
      RunCalibrateCommand(options, in, *out, progress);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(CalibrateCommandTest, SimulatedCalibrationIsWithinAMillimetreAndBeatsOpenCv) {
  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = folder_;
  // 14 poses: from the camera's place behind the arms (data/robots/vehicle.urdf)
  // the board is seen from farther than from the old front mount, and 12 poses
  // left the rotation at 0.101 deg.
  options.poses = 14;  // no --yes: the in-process simulator asks nothing
  std::istringstream no_answer;
  std::ostringstream out, progress;
  RunCalibrateCommand(options, no_answer, out, progress);
  EXPECT_THAT(out.str(), Not(HasSubstr("[y/N]")));
  EXPECT_THAT(out.str(), HasSubstr("planned 14 poses of the left arm"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "calibration_left.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "poses.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples" / "000.png"));
  const nlohmann::json s = Summary();
  EXPECT_GE(s["samples_used"].get<int>(), 6);
  EXPECT_EQ(s["samples_used"].get<int>() + s["samples_rejected"].get<int>(), 14);
  EXPECT_LT(s["error_to_truth_mm"].get<double>(), 1.0);
  EXPECT_LT(s["error_to_truth_deg"].get<double>(), 0.1);
  for (const auto& [name, method] : s["opencv"].items()) {
    ASSERT_TRUE(method["ok"].get<bool>()) << name;
    EXPECT_LT(s["error_to_truth_mm"].get<double>(), method["error_to_truth_mm"].get<double>())
        << name;
  }

  // Solving again from the saved samples gives the same residuals (no truth offline).
  const double residual_mm = s["residual_mm"].get<double>();
  CalibrateCommandOptions again;
  again.resolve_dir = folder_;
  std::ostringstream out2;
  RunCalibrateCommand(again, out2, progress);
  const nlohmann::json s2 = Summary();
  EXPECT_NEAR(s2["residual_mm"].get<double>(), residual_mm, 1e-6);
  EXPECT_FALSE(s2.contains("error_to_truth_mm"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "calibration_left.urdf"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "calibration_left_tf.sh"));

  // The accepted samples in ViSP's convention read back as they were taken,
  // and ViSP's solver on them gives what it gave in the run.
  const VispDataset visp = ReadVispDataset((fs::path(folder_) / "visp").string());
  ASSERT_EQ(static_cast<int>(visp.samples.size()), s["samples_used"].get<int>());
  EXPECT_TRUE(visp.has_camera);
  EXPECT_TRUE(fs::exists(visp.samples.front().image));
  CalibrateCommandOptions from_visp;
  from_visp.resolve_dir = (fs::path(folder_) / "visp").string();
  from_visp.out_dir = (fs::path(folder_) / "visp_solved").string();
  std::ostringstream out3;
  RunCalibrateCommand(from_visp, out3, progress);
  std::ifstream in(fs::path(from_visp.out_dir) / "summary.json");
  const nlohmann::json s3 = nlohmann::json::parse(in);
  EXPECT_NEAR(s3["residual_mm"].get<double>(), s["visp"]["residual_mm"].get<double>(), 1e-6);
}

// A data set written in ViSP's convention from a known eye-to-hand transform
// (robot base 0.8 m from the camera): `--resolve` gives it back and writes it
// in ViSP's, URDF's and tf's forms.
TEST_F(CalibrateCommandTest, ResolvesAViSPDataSetToTheTransformItWasMadeFrom) {
  const Eigen::Isometry3d rMc =
      MakeTransform(Eigen::Vector3d(0.8, -0.1, 0.45), Eigen::Vector3d(-2.0, 0.1, 1.5));
  const Eigen::Isometry3d eMo =
      MakeTransform(Eigen::Vector3d(0.0, 0.01, 0.06), Eigen::Vector3d(M_PI, 0.0, 0.2));
  FastRandom rng(11);
  for (int i = 1; i <= 9; ++i) {
    const Eigen::Isometry3d rMe = MakeTransform(
        Eigen::Vector3d(rng.Uniform(0.3, 0.5), rng.Uniform(-0.2, 0.2), rng.Uniform(0.2, 0.4)),
        Eigen::Vector3d(M_PI + rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5),
                        rng.Uniform(-1.0, 1.0)));
    WriteVispSample(folder_, i, rMe, rMc.inverse() * rMe * eMo, "");
  }
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("9 samples in ViSP's convention (eye-to-hand)"));
  const PoseError e = ComparePoses(ReadVispPose((fs::path(folder_) / "rPc.yaml").string()), rMc);
  EXPECT_LT(1e3 * e.translation_m, 0.1);
  EXPECT_LT(e.rotation_rad * 180.0 / M_PI, 0.01);
  EXPECT_TRUE(ReadVispPose((fs::path(folder_) / "ePo.yaml").string()).isApprox(eMo, 1e-6));
  std::ifstream urdf(fs::path(folder_) / "hand_eye.urdf");
  const std::string text((std::istreambuf_iterator<char>(urdf)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("<parent link=\"robot_base\"/>"));
  EXPECT_THAT(text, HasSubstr("<child link=\"camera_optical\"/>"));
  EXPECT_EQ(Summary()["setup"].get<std::string>(), "eye-to-hand");
}

TEST_F(CalibrateCommandTest, AViSPDataSetWithAPoseFileMissingIsNamed) {
  FastRandom rng(11);
  for (int i = 1; i <= 5; ++i) {
    const Eigen::Isometry3d rMe = MakeTransform(
        Eigen::Vector3d(0.4, 0.0, 0.3), Eigen::Vector3d(M_PI + 0.1 * i, rng.Uniform(-0.5, 0.5), 0));
    WriteVispSample(folder_, i, rMe, rMe, "");
  }
  fs::remove(fs::path(folder_) / "pose_rPe_2.yaml");
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out),
              HasSubstr("pose_rPe_2.yaml: missing (the robot pose of pose_cPo_2.yaml)"));
}

// The wizard's code path on the robot: the real SCS driver on the simulated
// bus (a pty), the simulated camera, the board where the hardware file's rig
// puts it; no autopilot. Reaches the simulator's accuracy.
TEST_F(CalibrateCommandTest, TheRealDriverOnTheSimulatedBusReachesTheSimulatorsAccuracy) {
  CalibrateCommandOptions options;
  options.arm = "right";
  options.out_dir = folder_;
  options.poses = 14;
  options.yes = true;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out, progress;
  RunCalibrateCommand(options, out, progress);
  EXPECT_THAT(out.str(), HasSubstr("arms     ok: simulated SCS bus on /dev/pts/"));
  EXPECT_THAT(out.str(),
              HasSubstr("at 30 deg/s; devices: " + DataPath("config/hardware_sim.yaml")));
  const nlohmann::json s = Summary();
  EXPECT_GE(s["samples_used"].get<int>(), 8);
  EXPECT_LE(s["error_to_truth_mm"].get<double>(), 1.0);
  EXPECT_LE(s["error_to_truth_deg"].get<double>(), 0.1);
}

// A servo that stops answering mid-run (the simulated bus silences it from
// 20 s of simulated time): both arms stop, the samples taken are kept, in a
// report that says why it stopped and holds nothing of the earlier one.
TEST_F(CalibrateCommandTest, AServoThatStopsAnsweringStopsTheArmsAndKeepsTheSamples) {
  testing::PlantEarlierReport(folder_);
  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = folder_;
  options.overwrite = true;
  options.poses = 14;
  options.yes = true;
  options.hardware_path =
      SimHardware({{"  sim_bus:\n", "  sim_bus:\n    silent_ids: [12]\n    faults_from_s: 20\n"}});
  std::ostringstream out;
  const std::string error = ErrorOf(options, &out);
  EXPECT_THAT(error, HasSubstr("servo left j2 (id 12) stopped answering on simulated SCS bus"));
  EXPECT_THAT(error, HasSubstr("the arms were stopped"));
  EXPECT_THAT(out.str(), HasSubstr("stopped: servo left j2 (id 12)"));
  const std::string samples_yaml = (fs::path(folder_) / "samples.yaml").string();
  ASSERT_TRUE(fs::exists(samples_yaml));
  const YAML::Node samples = YAML::LoadFile(samples_yaml)["samples"];
  EXPECT_GE(samples.size(), 2u);
  EXPECT_LT(samples.size(), 14u);
  EXPECT_THAT(error,
              HasSubstr(fmt::format("the {} samples taken so far are kept in {}/samples.yaml "
                                    "(solve them with `calibrate --resolve {}`)",
                                    samples.size(), folder_, folder_)));
  testing::ExpectReplacedTheEarlierReport(folder_);
  EXPECT_TRUE(Summary()["stopped_early"].get<bool>());
  EXPECT_EQ(Summary()["error"].get<std::string>(), error);
}

/// The person at the limp arm: each time the wizard waits for a line, the
/// hand moves the arm to the pose the wizard last suggested, a little off as a
/// hand places it, and presses Enter; after `samples` of them, q.
class Hand : public std::streambuf {
 public:
  /// `interrupt_at` > 0: the person presses Ctrl-C (SIGINT) at that move instead of Enter.
  Hand(World* world, Side side, const std::ostringstream* wizard, int samples, int interrupt_at = 0)
      : world_(world),
        side_(side),
        wizard_(wizard),
        samples_(samples),
        interrupt_at_(interrupt_at),
        rng_(3) {}
  int moves() const { return moves_; }

 protected:
  int_type underflow() override {
    if (moves_ < samples_) {
      const std::string text = wizard_->str();
      const std::size_t at = text.rfind("joints [");
      EXPECT_NE(at, std::string::npos) << "the wizard suggests no pose";
      std::istringstream joints(text.substr(at + 8, text.find(']', at) - at - 8));
      Eigen::VectorXd q(world_->arm(side_).q_true_rad().size());
      for (int j = 0; j < q.size(); ++j) {
        std::string v;
        std::getline(joints, v, ',');
        q[j] = (std::stod(v) + rng_.Uniform(-1.5, 1.5)) * M_PI / 180.0;
      }
      world_->arm(side_).MoveByHand(q);
      ++moves_;
      if (moves_ == interrupt_at_) std::raise(SIGINT);
      line_ = "\n";
    } else {
      line_ = "q\n";
    }
    setg(line_.data(), line_.data(), line_.data() + line_.size());
    return traits_type::to_int_type(*gptr());
  }

 private:
  World* world_;
  Side side_;
  const std::ostringstream* wizard_;
  int samples_, interrupt_at_, moves_ = 0;
  FastRandom rng_;
  std::string line_;
};

// Hand-guided samples through the real SCS driver on the simulated bus: the
// arm's torque goes off, the test's hand places it at the suggested poses, the
// joints come from the bus; the same accuracy as the planned poses.
TEST_F(CalibrateCommandTest, HandGuidedSamplesThroughTheBusReachTheSimulatorsAccuracy) {
  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = folder_;
  options.poses = 12;
  options.yes = true;
  options.hand_guided = true;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out, progress;
  const std::unique_ptr<HandEyeHardware> hw =
      OpenHandEyeHardware(options.hardware_path, "", options.seed, Side::kLeft, out);
  Hand hand(hw->world(), Side::kLeft, &out, 12);
  std::istream in(&hand);
  RunHandEyeWizard(options, *hw, in, out, progress);
  EXPECT_EQ(hand.moves(), 12);
  EXPECT_THAT(out.str(), HasSubstr("the left arm is limp"));
  EXPECT_THAT(out.str(), HasSubstr("taken: 1 accepted"));
  EXPECT_THAT(out.str(), HasSubstr("rotation axes span"));
  // Limp, the arm stayed where the hand left it (the driver followed it).
  const nlohmann::json s = Summary();
  EXPECT_GE(s["samples_used"].get<int>(), 8);
  EXPECT_LE(s["error_to_truth_mm"].get<double>(), 1.0);
  EXPECT_LE(s["error_to_truth_deg"].get<double>(), 0.1);
}

// Ctrl-C while samples are taken: the arms stop, the samples taken are kept.
TEST_F(CalibrateCommandTest, CtrlCStopsTheArmsAndKeepsTheSamples) {
  CalibrateCommandOptions options;
  options.arm = "left";
  options.out_dir = folder_;
  options.poses = 12;
  options.yes = true;
  options.hand_guided = true;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out, progress;
  const std::unique_ptr<HandEyeHardware> hw =
      OpenHandEyeHardware(options.hardware_path, "", options.seed, Side::kLeft, out);
  Hand hand(hw->world(), Side::kLeft, &out, 12, /*interrupt_at=*/4);
  std::istream in(&hand);
  try {
    RunHandEyeWizard(options, *hw, in, out, progress);
    FAIL() << "expected a stop";
  } catch (const HardwareError& e) {
    EXPECT_THAT(e.what(), HasSubstr("interrupted (Ctrl-C); the arms were stopped; the 3 samples "
                                    "taken so far are kept"));
  }
  EXPECT_EQ(hand.moves(), 4);
  EXPECT_EQ(YAML::LoadFile((fs::path(folder_) / "samples.yaml").string())["samples"].size(), 3u);
}

TEST_F(CalibrateCommandTest, HandGuidedSamplesNeedTheServoBus) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.hand_guided = true;
  options.yes = true;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out),
              HasSubstr("arms.backend: 'sim': hand-guided samples turn the arm's torque off"));
}

TEST_F(CalibrateCommandTest, DryRunChecksAndPlansWithoutMoving) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.poses = 8;
  options.dry_run = true;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  std::ostringstream out;
  EXPECT_EQ(ErrorOf(options, &out), "no error");
  EXPECT_THAT(out.str(), HasSubstr("ok       servo left j1 (id 11): 7.4 V"));
  EXPECT_THAT(out.str(), HasSubstr("ok       camera: frame"));
  EXPECT_THAT(out.str(), HasSubstr("planned 8 poses of the left arm"));
  EXPECT_THAT(out.str(), HasSubstr("dry run: nothing moved"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "plan.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "board.svg"));
  EXPECT_FALSE(fs::exists(fs::path(folder_) / "samples.yaml"));
}

TEST_F(CalibrateCommandTest, NothingMovesWithoutTheConfirmation) {
  CalibrateCommandOptions options;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  options.out_dir = folder_;
  options.poses = 4;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out, "n\n"), HasSubstr("not confirmed: nothing moved"));
  EXPECT_THAT(out.str(), HasSubstr("move the left arm through these 4 poses? [y/N]"));
  EXPECT_FALSE(fs::exists(fs::path(folder_) / "samples.yaml"));
}

// On a machine without the robot: every missing device is named with its port.
TEST_F(CalibrateCommandTest, DryRunWithTheExampleHardwareNamesTheMissingDevices) {
  CalibrateCommandOptions options;
  options.dry_run = true;
  options.hardware_path = DataPath("config/hardware_example.yaml");
  std::ostringstream out;
  const std::string error = ErrorOf(options, &out);
  EXPECT_THAT(error, HasSubstr("hardware_example.yaml: 2 device(s) did not open; nothing moved"));
  EXPECT_THAT(error, HasSubstr("arms (scs): servo bus: cannot open /dev/ttyUSB0"));
  EXPECT_THAT(error, HasSubstr("camera (realsense)"));
}

TEST_F(CalibrateCommandTest, RealArmsWithASimulatedCameraAreRefusedWithTheReason) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.hardware_path = SimHardware({{"backend: sim-bus", "backend: scs"}});
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out),
              HasSubstr("hw.yaml: arms.backend: 'scs' drives the real arms, but camera.backend "
                        "'sim' is simulated"));
}

TEST_F(CalibrateCommandTest, AllSamplesRejectedSaysSoAndKeepsThem) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.poses = 4;
  options.yes = true;
  // In-process devices whose arm never settles in time: every sample rejected.
  options.hardware_path = SimHardware(
      {{"backend: sim-bus", "backend: sim"}, {"settle_timeout_s: 3.0", "settle_timeout_s: 0.01"}});
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out), HasSubstr("only 0 usable samples"));
  EXPECT_THAT(out.str(), HasSubstr("rejected: arm not settled"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "samples" / "003.png"));
  EXPECT_TRUE(Summary()["stopped_early"].get<bool>());
}

// A dry run's report (the board, the plan) is an earlier report like any:
// refused without --overwrite, replaced with it.
TEST_F(CalibrateCommandTest, AnEarlierReportIsRefusedAndReplacedWithOverwrite) {
  CalibrateCommandOptions options;
  options.out_dir = folder_;
  options.poses = 4;
  options.dry_run = true;
  std::ostringstream out;
  testing::ExpectRefusesAnEarlierReport([&] { RunCalibrateCommand(options, out, out); }, folder_);
  options.overwrite = true;
  EXPECT_EQ(ErrorOf(options, &out), "no error");
  testing::ExpectReplacedTheEarlierReport(folder_);
  EXPECT_TRUE(Summary()["dry_run"].get<bool>());
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "board.svg"));
  EXPECT_THAT(out.str(), Not(HasSubstr(".partial-")));  // the folder named as it is now
}

// A run that fails before its first sample (the arm's move not confirmed)
// leaves the earlier report as it was, and nothing of its own.
TEST_F(CalibrateCommandTest, ARunFailingBeforeItsFirstSampleKeepsTheEarlierReportWhole) {
  testing::PlantEarlierReport(folder_);
  CalibrateCommandOptions options;
  options.hardware_path = DataPath("config/hardware_sim.yaml");
  options.out_dir = folder_;
  options.overwrite = true;
  options.poses = 4;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out, "n\n"), HasSubstr("not confirmed: nothing moved"));
  EXPECT_EQ(testing::ReadText(fs::path(folder_) / "summary.json"), "earlier");
  EXPECT_EQ(testing::ReadText(fs::path(folder_) / "earlier_only.txt"), "earlier");
  EXPECT_FALSE(fs::exists(fs::path(folder_) / "board.svg"));
  testing::ExpectNothingBeside(folder_);
}

TEST_F(CalibrateCommandTest, CorruptSamplesFileNamesTheField) {
  fs::create_directories(folder_);
  std::ofstream(fs::path(folder_) / "samples.yaml") << "platform: /nonexistent.yaml\narm: left\n";
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out), HasSubstr("samples.yaml: platform"));
}

TEST_F(CalibrateCommandTest, ANanJointReadingIsNamedAsSuch) {
  fs::create_directories(folder_);
  std::ofstream(fs::path(folder_) / "samples.yaml")
      << "platform: " << DataPath("config/platform_4dof.yaml") << "\narm: left\nboard: {}\n"
      << "samples:\n"
      << "  - {image: a.png, accepted: true, q_rad: [0.1, .nan, 0.2, 0.3],\n"
      << "     cMt: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.4, 0, 0, 0, 1], corners: []}\n";
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out, progress;
  try {
    RunCalibrateCommand(options, out, progress);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(),
                HasSubstr("samples.yaml: samples[0].q_rad[1]: nan is not a finite number"));
  }
}

// A board corner at infinity is named where it is read, not solved around
// (a file that says "refined" must hold the refined answer).
TEST_F(CalibrateCommandTest, ACornerAtInfinityIsNamedAsSuch) {
  fs::create_directories(folder_);
  std::ofstream(fs::path(folder_) / "samples.yaml")
      << "platform: " << DataPath("config/platform_4dof.yaml") << "\narm: left\nboard: {}\n"
      << "samples:\n"
      << "  - {image: a.png, accepted: true, q_rad: [0.1, 0.2, 0.2, 0.3],\n"
      << "     cMt: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.4, 0, 0, 0, 1],\n"
      << "     corners: [[0, 0, 0, 320, 240], [0.03, 0, 0, .inf, 240]]}\n";
  CalibrateCommandOptions options;
  options.resolve_dir = folder_;
  std::ostringstream out;
  EXPECT_THAT(ErrorOf(options, &out),
              HasSubstr("samples.yaml: samples[0].corners[1][3]: inf is not a finite number"));
}

TEST(CalibrationRigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  CalibrationRig rig = CalibrationRig::Load("");
  rig.joint_speed_deg_s = 200.0;
  EXPECT_THAT(
      testing::ValidationMessage(rig, "hw.yaml", "calibration."),
      HasSubstr(
          "hw.yaml: calibration.joint_speed_deg_s: 200 deg/s is above the upper bound 180 deg/s"));
  rig = CalibrationRig::Load("");
  rig.mount = "wrist";
  EXPECT_THAT(testing::ValidationMessage(rig, "hw.yaml", "calibration."),
              HasSubstr("hw.yaml: calibration.mount: 'wrist' is not one of: gripper, hand"));
}

// The hand-held intrinsics' coverage is read from the rig: the shipped hardware
// files say the code's defaults, and a bad value names the file, the key and the bound.
TEST(CalibrationRigTest, TheShippedFilesCoverageIsTheDefaultsAndABadValueIsNamed) {
  const CoverageConfig defaults;
  for (const char* file : {"config/hardware_sim.yaml", "config/hardware_example.yaml"}) {
    const CoverageConfig c = CalibrationRig::Load(DataPath(file)).coverage;
    EXPECT_EQ(c.grid_cols, defaults.grid_cols) << file;
    EXPECT_EQ(c.grid_rows, defaults.grid_rows) << file;
    EXPECT_EQ(c.min_corners_per_cell, defaults.min_corners_per_cell) << file;
    EXPECT_EQ(c.min_tilt_deg, defaults.min_tilt_deg) << file;
  }
  const fs::path path = fs::temp_directory_path() / "aerograsp_rig_coverage.yaml";
  const auto message = [&](const std::string& coverage) {
    std::ofstream(path) << "calibration:\n  coverage: " << coverage << "\n";
    try {
      CalibrationRig::Load(path.string());
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(CalibrationRig::Load("").coverage.grid_cols, defaults.grid_cols);
  EXPECT_THAT(
      message("{grid_cols: 9}"),
      HasSubstr(path.string() + ": calibration.coverage.grid_cols: 9 is above the upper bound 8"));
  EXPECT_THAT(
      message("{min_tilt_deg: 0.5}"),
      HasSubstr("calibration.coverage.min_tilt_deg: 0.5 deg is below the lower bound 1 deg"));
  EXPECT_THAT(message("{grid: 3}"), HasSubstr("calibration.coverage.grid: unknown key"));
  std::ofstream(path) << "calibration:\n  coverage: {grid_rows: 2, min_tilt_deg: 25}\n";
  const CoverageConfig read = CalibrationRig::Load(path.string()).coverage;
  EXPECT_EQ(read.grid_rows, 2);
  EXPECT_EQ(read.min_tilt_deg, 25.0);
  EXPECT_EQ(read.grid_cols, defaults.grid_cols);
  fs::remove(path);
}

}  // namespace
}  // namespace aerograsp
