#include "app/calibration/calibrate_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <streambuf>
#include <vector>

#include "app/calibration/calibrate_intrinsics.h"
#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_visp.h"
#include "app/calibration/hand_eye_moves.h"
#include "app/calibration/hand_eye_plan.h"
#include "app/calibration/hand_eye_samples.h"
#include "app/calibration/hand_eye_solve.h"
#include "app/calibration/interrupt_guard.h"
#include "app/calibration/tag_board_mesh.h"
#include "app/cli_checks.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "app/report/summary_file.h"
#include "app/runtime/telemetry_frames.h"
#include "core/collision.h"
#include "core/config.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace fs = std::filesystem;

void RunHandEyeWizard(const CalibrateCommandOptions& options, HandEyeHardware& hw, std::istream& in,
                      std::ostream& out, std::ostream& progress) {
  const Side side = ParseSide(options.arm);
  const CalibrationRig& rig = hw.rig();
  const TagBoardConfig& board = rig.board;
  RgbdCamera& camera = hw.camera();
  ArmsDriver& arms = hw.arms();
  const Platform& platform = hw.platform();
  const Side other = side == Side::kLeft ? Side::kRight : Side::kLeft;
  if (options.hand_guided && !hw.scs()) {
    throw ConfigError(fmt::format(
        "{}: arms.backend: '{}': hand-guided samples turn the arm's torque off, which needs the "
        "servo bus ('scs', or 'sim-bus' simulated)",
        hw.config().source, hw.config().arms.backend));
  }

  // Pre-flight: nothing has moved and the torque is as the servos had it.
  RgbdFrame frame;
  std::vector<std::string> failures = PreflightDevices(hw, &frame, out);
  TagDetector detector(board.family);
  // The arm may rest where the board faces away: then the board is looked for
  // again at the first pose, before the others.
  const std::string seen = BoardSeen(frame, rig, camera.intrinsics(), &detector);
  bool board_confirmed = seen.empty();
  out << fmt::format("  {:<8} board: {}\n", seen.empty() ? "ok" : "WARNING",
                     seen.empty() ? fmt::format("seen from the start pose ({} tag36h11 tags, "
                                                "{:.0f} mm)",
                                                board.rows * board.cols, 1e3 * board.tag_size_m)
                                  : seen +
                                        " from the start pose; looked for again at the "
                                        "first pose");
  if (!failures.empty()) {
    std::string all;
    for (const std::string& f : failures) all += "\n  " + f;
    throw HardwareError(
        fmt::format("{}: the pre-flight check failed; nothing moved:{}", hw.config().source, all));
  }

  // The plan: the poses visited, or suggested to the person guiding the arm.
  const std::vector<Eigen::VectorXd> poses = PlanPoses(
      platform, side, board, rig.eMt, arms.JointPositions(other), options.poses, options.seed);
  if (poses.empty()) {
    throw std::runtime_error(
        fmt::format("no arm pose of the {} arm shows the whole board to the camera while "
                    "clear of the safe volume",
                    SideName(side)));
  }
  out << fmt::format("planned {} poses of the {} arm (of {} requested){}; devices: {}\n",
                     poses.size(), SideName(side), options.poses,
                     options.hand_guided ? ", suggested to the hand"
                                         : fmt::format(" at {:.0f} deg/s", rig.joint_speed_deg_s),
                     hw.config().source);
  ShowPlan(poses, platform, side, rig, frame,
           options.out_dir.empty() ? "" : (fs::path(options.out_dir) / "plan.png").string(), out);
  if (options.dry_run) {
    out << "dry run: nothing moved\n";
    return;
  }
  // Devices named by a hardware file may be real arms; the in-process simulator moves nothing.
  if (!options.yes && !options.hardware_path.empty()) {
    out << (options.hand_guided
                ? fmt::format("turn the {} arm's torque off (hold it) to place it by hand? [y/N] ",
                              SideName(side))
                : fmt::format("move the {} arm through these {} poses? [y/N] ", SideName(side),
                              poses.size()))
        << std::flush;
    std::string answer;
    std::getline(in, answer);
    if (answer != "y" && answer != "yes") throw std::runtime_error("not confirmed: nothing moved");
  }

  TelemetrySink* sink = hw.telemetry();
  std::string phase = "preflight";
  const auto enter = [&](const std::string& to, const std::string& cause) {
    if (sink) sink->Transition({hw.now_s(), "calibrate", phase, to, cause});
    phase = to;
  };
  fs::create_directories(fs::path(options.out_dir) / "samples");
  const std::string visp_folder = (fs::path(options.out_dir) / "visp").string();
  fs::create_directories(visp_folder);
  SaveCameraXml(camera.intrinsics(), "Camera", (fs::path(visp_folder) / "camera.xml").string());
  const PlatformCollision collision(platform);
  std::vector<WizardSample> samples;
  const std::string samples_yaml = (fs::path(options.out_dir) / "samples.yaml").string();
  const InterruptGuard interrupt;
  auto keep = [&](const WizardSample& s) {
    samples.push_back(s);
    WriteSamplesYaml(samples_yaml, hw.config().platform, side, board,
                     samples);  // nothing is lost on an error
  };
  try {
    enter(options.hand_guided ? "hand-guided" : "moving",
          fmt::format("{} poses planned for the {} arm", poses.size(), SideName(side)));
    if (options.hand_guided) {
      hw.Arm(side);
      out << fmt::format(
          "the {} arm is limp: place it, let go, press Enter to take a sample; q "
          "and Enter to solve\n",
          SideName(side));
      for (std::size_t next = 0;;) {
        out << fmt::format("sample {}: suggested pose {}: joints [{}] deg\n", samples.size(), next,
                           Degrees(poses[next]))
            << std::flush;
        std::string line;
        if (!std::getline(in, line) || line == "q") break;
        CheckFaults(hw);
        const std::string moving = WaitStill(hw, side);
        const WizardSample s =
            TakeSample(hw, side, &detector, options.out_dir, samples.size(), moving, &frame);
        keep(s);
        next = (next + 1) % poses.size();
        if (s.accepted) {
          out << "  taken: " << DiversityLine(samples) << "\n";
        } else {
          out << "  rejected: " << s.reject_reason << "\n";
        }
      }
      hw.Stiffen(side);
    } else {
      hw.Arm();
      Progress bar(progress, "calibrate", static_cast<std::int64_t>(poses.size()), "poses");
      for (std::size_t k = 0; k < poses.size(); ++k) {
        const std::string refused = CheckMove(collision, side, arms.JointPositions(side), poses[k],
                                              arms.JointPositions(other));
        if (!refused.empty()) {
          out << fmt::format("  pose {:3d} skipped: {}\n", k, refused);
          continue;
        }
        const std::string unsettled = MoveAndSettle(hw, side, poses[k]);
        const WizardSample s =
            TakeSample(hw, side, &detector, options.out_dir, samples.size(), unsettled, &frame);
        if (!board_confirmed) {
          const std::string again = BoardSeen(frame, rig, camera.intrinsics(), &detector);
          if (!again.empty()) {
            throw StopRun{
                fmt::format("board: {} at pose {}, where the plan puts all of it in view: check "
                            "calibration.board and calibration.board_in_tool_* in {}",
                            again, k, rig.source)};
          }
          board_confirmed = true;
        }
        keep(s);
        bar.Update(static_cast<std::int64_t>(k + 1));
      }
      bar.Finish();
    }
  } catch (const StopRun& stop) {
    arms.Stop();
    enter("stopped", stop.reason);
    out << fmt::format("stopped: {}; both arms hold where they are (the {} arm at [{}] deg)\n",
                       stop.reason, SideName(side), Degrees(arms.JointPositions(side)));
    throw HardwareError(fmt::format(
        "{}; the arms were stopped; the {} samples taken so far are kept in {} (solve them with "
        "`calibrate --resolve {}`)",
        stop.reason, samples.size(), samples_yaml, options.out_dir));
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].accepted)
      out << fmt::format("  sample {:3d} rejected: {}\n", i, samples[i].reject_reason);
  }
  // In the simulator the truth is the world's platform's nominal geometry.
  std::optional<Eigen::Isometry3d> truth_cMb;
  if (World* world = hw.world())
    truth_cMb = world->platform().dMc().inverse() * world->platform().dMb(side);
  enter("solving", fmt::format("{} samples taken", samples.size()));
  SolveHandEyeAndReport(options.out_dir, hw.config().platform, side, board, samples, truth_cMb,
                        out);
  enter("done", "solved");
}

namespace {

/// Forwards what is written to `to` line by line (and at each flush) with the
/// report's temporary folder named as it will be after the commit.
class ShownPaths : public std::streambuf {
 public:
  ShownPaths(std::ostream& to, const ReportFolder& folder) : to_(to), folder_(folder) {}
  ~ShownPaths() override { sync(); }
  ShownPaths(const ShownPaths&) = delete;
  ShownPaths& operator=(const ShownPaths&) = delete;

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    pending_.push_back(traits_type::to_char_type(c));
    if (pending_.back() == '\n') sync();
    return c;
  }
  int sync() override {
    if (!pending_.empty()) to_ << folder_.Final(pending_);
    pending_.clear();
    to_.flush();
    return to_ ? 0 : -1;
  }

 private:
  std::ostream& to_;
  const ReportFolder& folder_;
  std::string pending_;
};

/// The same exception type as the one being handled, with `message`.
[[noreturn]] void RethrowWith(const std::string& message) {
  try {
    throw;
  } catch (const HardwareError&) {
    throw HardwareError(message);
  } catch (const ConfigError&) {
    throw ConfigError(message);
  } catch (...) {
    throw std::runtime_error(message);
  }
}

/// Runs `run` (the hand-eye wizard or the intrinsics) with its options'
/// out_dir a ReportFolder's temporary folder and its output naming the final
/// one (without --out: as given). A run that throws after `taken` (the file
/// its samples are kept in) was written commits them with a summary.json
/// saying why it stopped, then throws the same error.
void InReportFolder(const CalibrateCommandOptions& options, const std::string& taken,
                    std::ostream& out,
                    const std::function<void(const CalibrateCommandOptions&, std::ostream&)>& run) {
  if (options.out_dir.empty()) {
    run(options, out);
    return;
  }
  ReportFolder folder(options.out_dir, options.overwrite);
  ShownPaths shown(out, folder);
  std::ostream shown_out(&shown);
  CalibrateCommandOptions in_folder = options;
  in_folder.out_dir = folder.path();
  const fs::path work(folder.path());
  try {
    run(in_folder, shown_out);
  } catch (const std::exception& e) {
    shown_out.flush();
    const std::string error = folder.Final(e.what());
    if (fs::exists(work / taken)) {
      if (!fs::exists(work / "summary.json")) {
        WriteSummaryFile(
            folder.path(),
            nlohmann::json{{"stopped_early", true}, {"error", error}, {"samples_file", taken}}.dump(
                2));
      }
      folder.Commit();
    }  // else nothing was taken: an earlier report stays as it was
    RethrowWith(error);
  }
  shown_out.flush();
  if (!fs::exists(work / "summary.json")) {  // a dry run: the board and the plan
    WriteSummaryFile(folder.path(), nlohmann::json{{"dry_run", true}}.dump(2));
  }
  folder.Commit();
}

void RunWizard(const CalibrateCommandOptions& options, std::istream& in, std::ostream& out,
               std::ostream& progress) {
  const Side side = ParseSide(options.arm);
  if (!options.out_dir.empty()) {  // the board to print, before any device is needed
    WriteBoardSvg(CalibrationRig::Load(options.hardware_path).board,
                  (fs::path(options.out_dir) / "board.svg").string());
  }
  const std::unique_ptr<HandEyeHardware> hw =
      OpenHandEyeHardware(options.hardware_path, options.world_config, options.seed, side, out);
  CommandTelemetry telemetry;
  if (!options.out_dir.empty() && !options.dry_run) {
    telemetry =
        OpenTelemetry(LoadTelemetryConfig(options.telemetry), options.out_dir, "calibrate",
                      [&out](const std::string& line) { out << "telemetry: " << line << "\n"; });
  }
  if (TelemetrySink* sink = telemetry.sink()) {
    sink->StaticTransforms(hw->now_s(), PlatformStaticFrames(hw->platform()));
    sink->Transition({hw->now_s(), "calibrate", "idle", "preflight", "start"});
    hw->SetTelemetry(sink);
  }
  hw->SetEmergencyStop(telemetry.emergency_stop.get(),
                       [&out](const std::string& line) { out << "telemetry: " << line << "\n"; });
  try {
    RunHandEyeWizard(options, *hw, in, out, progress);
  } catch (...) {
    hw->SetTelemetry(nullptr);
    hw->SetEmergencyStop(nullptr);
    telemetry.Close();
    throw;
  }
  hw->SetTelemetry(nullptr);
  hw->SetEmergencyStop(nullptr);
  const std::string mcap = telemetry.Close();
  if (!mcap.empty()) out << "wrote " << mcap << "\n";
}

}  // namespace

void RunCalibrateCommand(const CalibrateCommandOptions& options, std::istream& in,
                         std::ostream& out, std::ostream& progress) {
  if (!options.resolve_dir.empty()) {
    if (IsIntrinsicsFolder(options.resolve_dir)) {
      ResolveIntrinsics(options.resolve_dir, out);
      return;
    }
    const std::string samples_yaml = (fs::path(options.resolve_dir) / "samples.yaml").string();
    if (!fs::exists(samples_yaml) && IsVispDataset(options.resolve_dir)) {
      ResolveVispDataset(options.resolve_dir, ParseHandEyeSetup(options.setup, "--setup"),
                         options.tag_size_m,
                         options.out_dir.empty() ? options.resolve_dir : options.out_dir, out);
      return;
    }
    if (!fs::exists(samples_yaml)) {
      throw ConfigError(options.resolve_dir +
                        ": holds neither samples.yaml (aerograsp's samples) nor pose_rPe_N.yaml / "
                        "pose_cPo_N.yaml files (ViSP's convention) nor intrinsics views");
    }
    std::string platform_path;
    Side side;
    TagBoardConfig board;
    const std::vector<WizardSample> samples =
        ReadSamplesYaml(samples_yaml, &platform_path, &side, &board);
    SolveHandEyeAndReport(options.resolve_dir, platform_path, side, board, samples, std::nullopt,
                          out);
    return;
  }
  if (options.intrinsics) {
    InReportFolder(options, "views.yaml", out,
                   [&progress](const CalibrateCommandOptions& o, std::ostream& shown) {
                     RunCalibrateIntrinsics(o, shown, progress);
                   });
    return;
  }
  if (options.out_dir.empty() && !options.dry_run)
    throw ConfigError("--out: an output folder is required");
  InReportFolder(options, "samples.yaml", out,
                 [&in, &progress](const CalibrateCommandOptions& o, std::ostream& shown) {
                   RunWizard(o, in, shown, progress);
                 });
}

void RunCalibrateCommand(const CalibrateCommandOptions& options, std::ostream& out,
                         std::ostream& progress) {
  RunCalibrateCommand(options, std::cin, out, progress);
}

void AddCalibrateOptions(CLI::App* cmd, CalibrateCommandOptions* o) {
  cmd->add_option("--arm", o->arm, "Arm to calibrate")
      ->capture_default_str()
      ->check(CLI::IsMember({"left", "right"}));
  cmd->add_flag(
      "--intrinsics", o->intrinsics,
      "Calibrate the camera's intrinsics from a board shown in varied poses (not an arm); with "
      "--hardware the board is held by hand and the wizard says which image parts and tilts "
      "are still missing");
  cmd->add_option("--out", o->out_dir, "Folder for the samples, the calibration and the report");
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--resolve", o->resolve_dir,
                  "Solve again from the samples saved in this folder (ours, or a data set "
                  "in ViSP's convention: pose_rPe_N.yaml, pose_cPo_N.yaml, camera.xml)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--setup", o->setup,
                  "With --resolve on a ViSP data set: the camera fixed and the object on the "
                  "gripper (eye-to-hand) or the camera on the gripper (eye-in-hand)")
      ->capture_default_str()
      ->check(CLI::IsMember({"eye-to-hand", "eye-in-hand"}));
  cmd->add_option("--tag-size", o->tag_size_m,
                  "With --resolve on a ViSP data set without pose_cPo files: the tag36h11 "
                  "tag's black square (m); its pose is then detected in each image")
      ->check(cli::Range(0.005, 1.0));
  cmd->add_option("--poses", o->poses,
                  "Arm poses (or board views, with --intrinsics; with --intrinsics --hardware "
                  "the fewest hand-held samples) to visit")
      ->capture_default_str()
      ->check(cli::Range(4, 100));
  cmd->add_option("--seed", o->seed, "World and pose-planning seed")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--world", o->world_config, "World YAML")->check(CLI::ExistingFile);
  cmd->add_option("--hardware", o->hardware_path,
                  "Hardware YAML (the built-in simulation when absent): the real bus and "
                  "camera, or simulated ones; its `calibration` section is the rig")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--dry-run", o->dry_run,
                "Pre-flight check and the planned poses only: nothing moves");
  cmd->add_flag("--yes", o->yes,
                "Do not ask for a confirmation before the arm moves (scripts; --hardware only)");
  cmd->add_flag("--hand-guided", o->hand_guided,
                "Torque off on the arm: place it by hand, Enter takes a sample, q solves");
  AddTelemetryOptions(cmd, &o->telemetry);
}

}  // namespace aerograsp
