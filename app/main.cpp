// The aerograsp command line.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <vector>

#include "app/benchmarks/fault_benchmark.h"
#include "app/benchmarks/mission_benchmark.h"
#include "app/benchmarks/perception_benchmark.h"
#include "app/benchmarks/render_benchmark.h"
#include "app/benchmarks/servo_benchmark.h"
#include "app/benchmarks/servo_bus_benchmark.h"
#include "app/calibration/calibrate_command.h"
#include "app/cli_checks.h"
#include "app/commands/bench_command.h"
#include "app/commands/convert_command.h"
#include "app/commands/dataset_command.h"
#include "app/commands/hardware_check_command.h"
#include "app/commands/mission_command.h"
#include "app/commands/object_command.h"
#include "app/commands/plan_command.h"
#include "app/commands/record_command.h"
#include "app/commands/replay_command.h"
#include "app/commands/robot_command.h"
#include "app/commands/telemetry_options.h"
#include "app/exit_codes.h"
#include "core/data_dir.h"

#ifndef AEROGRASP_VERSION
#define AEROGRASP_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  CLI::App app{
      "aerograsp: dual-arm aerial grasping of known objects (detection, 6D pose, grasp "
      "planning, visual servoing) on a PX4 hexacopter with a RealSense D435."};
  app.set_version_flag("--version", std::string("aerograsp ") + AEROGRASP_VERSION);
  app.require_subcommand(1);

  aerograsp::RobotCommandOptions robot;
  robot.config_path = aerograsp::DataPath("config/platform_4dof.yaml");
  CLI::App* robot_cmd = app.add_subcommand(
      "robot", "Print the platform: frame tree, camera, safe volume, arm chains, limits, reach");
  robot_cmd->add_option("config", robot.config_path, "Platform YAML")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  robot_cmd
      ->add_option("--samples", robot.reach_samples,
                   "Random configurations sampled for the workspace figures")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 10000000));
  robot_cmd->add_option("--seed", robot.seed, "Seed of the workspace samples")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  robot_cmd->add_option("--plot", robot.plot_path,
                        "Write a PNG of the platform (side and front views, arms at home)");

  aerograsp::RecordCommandOptions record;
  CLI::App* record_cmd = app.add_subcommand(
      "record",
      "Simulate a hover in front of the object and write an RGB-D sequence with ground truth");
  record_cmd->add_option("--out", record.out_dir, "Sequence folder to create")->required();
  record_cmd->add_option("--frames", record.frames, "Number of frames")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 1000000));
  record_cmd->add_option("--seed", record.seed, "World seed (same seed, same sequence)")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  record_cmd
      ->add_option("--world", record.world_config,
                   "World YAML (default: data/config/world_default.yaml)")
      ->check(CLI::ExistingFile);
  record_cmd->add_option("--object", record.object,
                         "Object: a shipped name (crawler, u_shape, pipe) or a model path");
  record_cmd->add_option("--motion", record.motion, "Object motion along the pipe")
      ->check(CLI::IsMember({"static", "crawl"}));
  record_cmd->add_flag("--overwrite", record.overwrite, "Replace a sequence already in --out");
  record_cmd
      ->add_option("--occlude-at", record.occlude_at_s,
                   "A panel hides the object fully from this simulated time on, s (off by default)")
      ->check(aerograsp::cli::Range(0.0, 1e6));
  record_cmd
      ->add_option("--occlude-for", record.occlude_for_s, "How long the panel hides the object, s")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1e-3, 1e6));
  record_cmd
      ->add_option("--occlude-every", record.occlude_every_s,
                   "The panel hides the object again every this many seconds (0: once)")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(0.0, 1e6));

  CLI::App* benchmark_cmd = app.add_subcommand(
      "benchmark", "Speed and accuracy figures of one stage, printed and in DIR/summary.json");
  benchmark_cmd->require_subcommand(1);
  aerograsp::RenderBenchmarkOptions render_bench;
  CLI::App* render_bench_cmd =
      benchmark_cmd->add_subcommand("render", "Simulated D435 frame: ray casting and sensor model");
  render_bench_cmd->add_option("--out", render_bench.out_dir, "Folder for summary.json");
  render_bench_cmd->add_flag("--overwrite", render_bench.overwrite,
                             "Replace a report already in --out");
  render_bench_cmd->add_option("--frames", render_bench.frames, "Frames to render")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 100000));
  render_bench_cmd->add_option("--seed", render_bench.seed, "World seed")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  render_bench_cmd->add_option("--world", render_bench.world_config, "World YAML")
      ->check(CLI::ExistingFile);
  aerograsp::ServoBenchmarkOptions servo_benchmark;
  CLI::App* servo_benchmark_cmd =
      benchmark_cmd->add_subcommand("servo",
                                    "Dual-arm servo: convergence, iterations, step time, "
                                    "safe-volume entries; KDL IK on the same targets");
  aerograsp::AddServoBenchmarkOptions(servo_benchmark_cmd, &servo_benchmark);
  // ---- benchmark servo-bus: closed-loop cycle on the simulated SCS bus ----
  aerograsp::ServoBusBenchmarkOptions servo_bus_bench;
  CLI::App* servo_bus_bench_cmd =
      benchmark_cmd->add_subcommand("servo-bus",
                                    "Arm driver cycle (sync write to all servos, read every "
                                    "position) on the simulated bus (pty)");
  servo_bus_bench_cmd->add_option("--out", servo_bus_bench.out_dir, "Folder for summary.json");
  servo_bus_bench_cmd->add_flag("--overwrite", servo_bus_bench.overwrite,
                                "Replace a report already in --out");
  servo_bus_bench_cmd->add_option("--cycles", servo_bus_bench.cycles, "Bus cycles to time")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(10, 1000000));
  servo_bus_bench_cmd->add_option("--world", servo_bus_bench.world_config, "World YAML")
      ->check(CLI::ExistingFile);
  // ---- end benchmark servo-bus ----
  // ---- benchmark faults: seeded missions with one device fault each ----
  aerograsp::FaultBenchmarkOptions fault_bench;
  CLI::App* fault_bench_cmd = benchmark_cmd->add_subcommand(
      "faults",
      "Seeded missions with one fault each at a random time (servo silent or slow, corrupted "
      "bus, lost link, refused commands, frozen camera, no depth, object knocked off): safe "
      "state and its latency per kind");
  aerograsp::AddFaultBenchmarkOptions(fault_bench_cmd, &fault_bench);
  // ---- end benchmark faults ----
  // ---- benchmark missions: every arm, object and motion, seeded ----
  aerograsp::MissionBenchmarkOptions mission_bench;
  CLI::App* mission_bench_cmd = benchmark_cmd->add_subcommand(
      "missions",
      "Seeded missions of every combination of arms (4dof, 6dof), object (crawler, pipe, "
      "u_shape) and motion (crawl, static): success on the first attempt and within 3, time to "
      "grasp, closes, tool error, safety, worst servo step, real-time factor per combination");
  aerograsp::AddMissionBenchmarkOptions(mission_bench_cmd, &mission_bench);
  // ---- end benchmark missions ----
  // ---- benchmark perception: plain meshes against coloured ones ----
  aerograsp::PerceptionBenchmarkOptions perception_bench;
  CLI::App* perception_bench_cmd = benchmark_cmd->add_subcommand(
      "perception",
      "The tracker with plain meshes (colours stripped) against coloured ones on recorded "
      "sequences, ViSP's tracker beside");
  perception_bench_cmd->add_option("--out", perception_bench.out_dir, "Folder for everything")
      ->required();
  perception_bench_cmd->add_flag("--overwrite", perception_bench.overwrite,
                                 "Replace a report already in --out");
  perception_bench_cmd->add_option("--objects", perception_bench.objects, "Objects")
      ->capture_default_str();
  perception_bench_cmd->add_option("--motions", perception_bench.motions, "Object motions")
      ->capture_default_str()
      ->check(CLI::IsMember({"static", "crawl"}));
  perception_bench_cmd->add_option("--frames", perception_bench.frames, "Frames per sequence")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(10, 100000));
  perception_bench_cmd->add_option("--seed", perception_bench.seed, "World seed")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  perception_bench_cmd->add_flag("!--no-peer", perception_bench.run_peer,
                                 "Do not run ViSP's tracker beside ours");
  perception_bench_cmd
      ->add_option("--perception", perception_bench.perception_config,
                   "Perception YAML [the code's defaults]")
      ->check(CLI::ExistingFile);
  // ---- end benchmark perception ----
  // ---- hardware-check: open each device of a hardware config ----
  aerograsp::HardwareCheckOptions hardware_check;
  CLI::App* hardware_check_cmd = app.add_subcommand(
      "hardware-check",
      "Open each device of a hardware configuration and report it (nothing moves)");
  hardware_check_cmd
      ->add_option("--hardware", hardware_check.config_path,
                   "Hardware YAML (e.g. data/config/hardware_sim.yaml)")
      ->required()
      ->check(CLI::ExistingFile);
  hardware_check_cmd->add_option("--seed", hardware_check.seed, "World seed of simulated devices")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  // ---- end hardware-check ----
  // ---- plan: dual grasps of an object ----
  aerograsp::PlanCommandOptions plan;
  plan.config_path = aerograsp::DataPath("config/platform_4dof.yaml");
  std::vector<double> plan_xyz, plan_rpy;
  CLI::App* plan_cmd = app.add_subcommand(
      "plan",
      "Rank the dual grasps of an object (shipped name or mesh path); table, PNG, summary.json");
  plan_cmd->add_option("object", plan.object, "Object name (shipped or imported) or a mesh file")
      ->required();
  plan_cmd->add_option("--out", plan.out_dir, "Output folder (summary.json, grasps.png)")
      ->required();
  plan_cmd->add_flag("--overwrite", plan.overwrite, "Replace a report already in --out");
  plan_cmd->add_option("--config", plan.config_path, "Platform YAML")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  plan_cmd
      ->add_option(
          "--object-xyz", plan_xyz,
          "Object centre (bounding box) in the body frame d (FRD), m [default 0.10 0 0.46]")
      ->expected(3)
      ->check(aerograsp::cli::Finite());
  plan_cmd
      ->add_option("--object-rpy", plan_rpy, "Object roll pitch yaw in d, deg [default 180 0 90]")
      ->expected(3)
      ->check(aerograsp::cli::Finite());
  plan_cmd->add_option("--resolution", plan.resolution_m, "Contact ray grid, m")
      ->capture_default_str()
      ->check(aerograsp::cli::Finite());
  plan_cmd
      ->add_option("--depth-min", plan.depth_min_m,
                   "Contacts at least this far behind the tool point, m")
      ->capture_default_str()
      ->check(aerograsp::cli::Finite());
  plan_cmd
      ->add_option("--reach-margin", plan.reach_margin_m,
                   "A grasp is robust when it stays feasible with the object moved this far along "
                   "each axis, m")
      ->capture_default_str()
      ->check(aerograsp::cli::Finite());
  plan_cmd
      ->add_option("--edge-margin", plan.edge_margin_m,
                   "Grasps whose contacts stay on their faces with the object shifted this far "
                   "along them rank first, m")
      ->capture_default_str()
      ->check(aerograsp::cli::Finite());
  plan_cmd->add_flag("--place", plan.place,
                     "Plan where the mission holds the object: the placement searched around "
                     "--object-xyz, upright at --object-rpy's yaw, with the mission's planner and "
                     "placement settings (data/config/mission_default.yaml; the planner options "
                     "above are then ignored)");
  plan_cmd->add_option("--mass", plan.mass_kg, "Mass of a bare mesh, kg")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1e-6, 1e4));
  plan_cmd->add_option("--cache-dir", plan.cache_dir, "Contact cache folder [~/.cache/aerograsp]");
  plan_cmd->add_flag("!--no-cache", plan.use_cache, "Neither read nor write the contact cache");
  plan_cmd->add_option("--top", plan.top, "Rows of the table")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 1000));
  plan_cmd->add_option("--repeats", plan.repeats, "Timing repetitions (median)")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 1000));
  // ---- end plan ----

  aerograsp::CalibrateCommandOptions calibrate;
  CLI::App* calibrate_cmd = app.add_subcommand("calibrate",
                                               "Camera-to-arm calibration from an AprilTag board "
                                               "on the gripper, or the camera's intrinsics");
  calibrate_cmd->add_option("--arm", calibrate.arm, "Arm to calibrate")
      ->capture_default_str()
      ->check(CLI::IsMember({"left", "right"}));
  calibrate_cmd->add_flag(
      "--intrinsics", calibrate.intrinsics,
      "Calibrate the camera's intrinsics from a board shown in varied poses (not an arm); with "
      "--hardware the board is held by hand and the wizard says which image parts and tilts "
      "are still missing");
  calibrate_cmd->add_option("--out", calibrate.out_dir,
                            "Folder for the samples, the calibration and the report");
  calibrate_cmd->add_flag("--overwrite", calibrate.overwrite, "Replace a report already in --out");
  calibrate_cmd
      ->add_option("--resolve", calibrate.resolve_dir,
                   "Solve again from the samples saved in this folder (ours, or a data set "
                   "in ViSP's convention: pose_rPe_N.yaml, pose_cPo_N.yaml, camera.xml)")
      ->check(CLI::ExistingDirectory);
  calibrate_cmd
      ->add_option("--setup", calibrate.setup,
                   "With --resolve on a ViSP data set: the camera fixed and the object on the "
                   "gripper (eye-to-hand) or the camera on the gripper (eye-in-hand)")
      ->capture_default_str()
      ->check(CLI::IsMember({"eye-to-hand", "eye-in-hand"}));
  calibrate_cmd
      ->add_option("--tag-size", calibrate.tag_size_m,
                   "With --resolve on a ViSP data set without pose_cPo files: the tag36h11 "
                   "tag's black square (m); its pose is then detected in each image")
      ->check(aerograsp::cli::Range(0.005, 1.0));
  calibrate_cmd
      ->add_option("--poses", calibrate.poses,
                   "Arm poses (or board views, with --intrinsics; with --intrinsics --hardware "
                   "the fewest hand-held samples) to visit")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(4, 100));
  calibrate_cmd->add_option("--seed", calibrate.seed, "World and pose-planning seed")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  calibrate_cmd->add_option("--world", calibrate.world_config, "World YAML")
      ->check(CLI::ExistingFile);
  calibrate_cmd
      ->add_option("--hardware", calibrate.hardware_path,
                   "Hardware YAML (the built-in simulation when absent): the real bus and "
                   "camera, or simulated ones; its `calibration` section is the rig")
      ->check(CLI::ExistingFile);
  calibrate_cmd->add_flag("--dry-run", calibrate.dry_run,
                          "Pre-flight check and the planned poses only: nothing moves");
  calibrate_cmd->add_flag(
      "--yes", calibrate.yes,
      "Do not ask for a confirmation before the arm moves (scripts; --hardware only)");
  calibrate_cmd->add_flag(
      "--hand-guided", calibrate.hand_guided,
      "Torque off on the arm: place it by hand, Enter takes a sample, q solves");
  aerograsp::AddTelemetryOptions(calibrate_cmd, &calibrate.telemetry);
  // ---- replay and dataset: perception ----
  aerograsp::ReplayCommandOptions replay;
  std::vector<double> replay_init;
  CLI::App* replay_cmd = app.add_subcommand("replay",
                                            "Run perception on a recorded sequence: poses.csv, "
                                            "summary.json, plots; ViSP's tracker beside it");
  replay_cmd
      ->add_option("sequence", replay.sequence,
                   "Recording: sequence folder, RealSense .bag or TUM RGB-D folder")
      ->required()
      ->check(CLI::ExistingPath);
  replay_cmd
      ->add_option("--out", replay.out_dir,
                   "Output folder (index.html, summary.json, poses.csv, pose_vs_truth.png)")
      ->required();
  replay_cmd->add_flag("--overwrite", replay.overwrite, "Replace a report already in --out");
  replay_cmd->add_option("--object", replay.object,
                         "Object (shipped name or model path) [from sequence.yaml]");
  replay_cmd->add_option("--detector", replay.detector,
                         "Detector ONNX [data/objects/NAME/detector.onnx]");
  replay_cmd->add_flag("!--no-detector", replay.use_detector,
                       "No CNN: global registration on the whole frame");
  replay_cmd->add_option("--init-pose", replay_init, "Known first cMo: x y z (m) qw qx qy qz")
      ->expected(7)
      ->check(aerograsp::cli::Finite());
  replay_cmd->add_flag("--init-from-truth", replay.init_from_truth,
                       "Known first cMo from groundtruth.csv");
  replay_cmd->add_flag("!--no-peer", replay.run_peer,
                       "Do not run ViSP's vpMbGenericTracker beside ours");
  replay_cmd
      ->add_option(
          "--filter-frame", replay.filter_frame,
          "Pose filter frame: camera, or world (camera poses from the recorded vehicle states)")
      ->capture_default_str();
  replay_cmd->add_option("--platform", replay.platform,
                         "Platform YAML for the camera mount [config/platform_4dof.yaml]");
  replay_cmd->add_option("--frames", replay.max_frames, "Process at most this many frames (0: all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  replay_cmd
      ->add_option(
          "--perception", replay.perception_config,
          "Perception YAML (see data/config/perception_default.yaml) [the code's defaults]")
      ->check(CLI::ExistingFile);
  aerograsp::AddTelemetryOptions(replay_cmd, &replay.telemetry);
  // Recordings from other sources: options shared by replay and convert.
  std::vector<double> replay_wMo, convert_wMo;
  double replay_gap_ms = 0.0, convert_gap_ms = 0.0;
  auto recording_options = [](CLI::App* cmd, aerograsp::RecordingOptions* o,
                              std::vector<double>* wMo, double* gap_ms) {
    cmd->add_option("--intrinsics", o->intrinsics_file,
                    "TUM folders: colour intrinsics (ViSP camera XML or YAML)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--object-in-world", *wMo,
                    "TUM folders: the object in groundtruth.txt's world, x y z (m) qw qx qy qz "
                    "(gives the ground truth)")
        ->expected(7)
        ->check(aerograsp::cli::Finite());
    cmd->add_option("--max-pair-gap-ms", *gap_ms,
                    ".bag and TUM: pair colour and depth frames at most this far apart (ms) "
                    "[one depth frame period]")
        ->check(aerograsp::cli::Range(0.0, 1e6));
  };
  recording_options(replay_cmd, &replay.recording, &replay_wMo, &replay_gap_ms);
  aerograsp::ConvertCommandOptions convert;
  CLI::App* convert_cmd = app.add_subcommand(
      "convert", "Write a RealSense .bag or a TUM RGB-D folder as a sequence folder");
  convert_cmd->add_option("input", convert.input, "RealSense .bag, TUM RGB-D or sequence folder")
      ->required()
      ->check(CLI::ExistingPath);
  convert_cmd->add_option("--out", convert.out_dir, "Sequence folder to write")->required();
  convert_cmd->add_option("--object", convert.object,
                          "Object recorded in sequence.yaml (shipped name or model path)");
  convert_cmd->add_option("--frames", convert.max_frames, "At most this many frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  convert_cmd->add_flag("--overwrite", convert.overwrite, "Replace a sequence already in --out");
  recording_options(convert_cmd, &convert.recording, &convert_wMo, &convert_gap_ms);

  aerograsp::DatasetCommandOptions dataset;
  CLI::App* dataset_cmd = app.add_subcommand(
      "dataset",
      "Render labelled detector training images of an object (160x120 PNG + labels.csv)");
  dataset_cmd->add_option("--object", dataset.object, "Shipped object name or model path")
      ->required();
  dataset_cmd->add_option("--out", dataset.out_dir, "Output folder")->required();
  dataset_cmd->add_option("--count", dataset.count, "Images")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 1000000));
  dataset_cmd->add_option("--seed", dataset.seed, "Seed (same seed, same images)")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  dataset_cmd->add_flag("--overwrite", dataset.overwrite, "Replace a dataset already in --out");
  dataset_cmd
      ->add_option("--on-support", dataset.on_support,
                   "Fraction of images with the object lying on the support pipe, seen from the "
                   "vehicle's camera "
                   "with its arms in view")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(0.0, 1.0));
  // ---- end replay and dataset ----

  // ---- mission: the simulated mission end to end ----
  aerograsp::MissionCommandOptions mission;
  CLI::App* mission_cmd = app.add_subcommand("mission",
                                             "Fly a full grasping mission in the simulator: "
                                             "take-off, approach, detect, grasp with both arms, "
                                             "lift, home, land; report in DIR");
  aerograsp::AddMissionOptions(mission_cmd, &mission);
  // ---- end mission ----
  // ---- object import: a user's own object ----
  aerograsp::ObjectImportOptions object_import;
  CLI::App* object_cmd =
      app.add_subcommand("object", "Bring in a user's object (import) and describe one (show)");
  object_cmd->require_subcommand(1);
  CLI::App* import_cmd = object_cmd->add_subcommand(
      "import",
      "Check, repair and measure a mesh (PLY, OBJ, STL, ViSP .cao; mass, symmetry) and store it "
      "as an object every command finds by name (docs/objects.md)");
  import_cmd->add_option("mesh", object_import.mesh_path, "Mesh file")
      ->required()
      ->check(CLI::ExistingFile);
  import_cmd->add_option("--name", object_import.name, "Object name (--object NAME)")->required();
  import_cmd->add_option("--units", object_import.units, "Length unit of the file")
      ->capture_default_str()
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  import_cmd
      ->add_option("--mass", object_import.mass_kg,
                   "Mass, kg [the volume at 300 kg/m^3, an estimate]")
      ->check(aerograsp::cli::Range(1e-6, 1e4));
  import_cmd->add_option("--objects-dir", object_import.objects_dir,
                         "Folder to store it in [$AEROGRASP_OBJECTS_DIR, else data/objects]");
  import_cmd
      ->add_option("--config", object_import.config_path,
                   "Import settings [data/config/object_import.yaml]")
      ->check(CLI::ExistingFile);
  import_cmd->add_flag("--overwrite", object_import.overwrite,
                       "Replace an object of that name in the folder");
  std::string object_show;
  bool object_show_folder = false;
  CLI::App* show_cmd = object_cmd->add_subcommand(
      "show", "Where an object is and what it is (mesh, mass, symmetry, detector)");
  show_cmd->add_option("object", object_show, "Object name or path")->required();
  show_cmd->add_flag("--folder", object_show_folder, "Print the object's folder only");
  // ---- end object import ----
  // ---- bench: perception and servo against tags on a test stand ----
  aerograsp::BenchCommandOptions bench;
  std::vector<double> bench_board_pose;
  CLI::App* bench_cmd =
      app.add_subcommand("bench",
                         "Vehicle on a test stand, the object with a tag board moved by script "
                         "(simulator) or by hand (--hardware): perception against the tags, "
                         "servo error to the grasp or a hover point off it; report in DIR");
  bench_cmd
      ->add_option("--out", bench.out_dir, "Report folder (index.html, summary.json, frames.csv)")
      ->required();
  bench_cmd->add_flag("--overwrite", bench.overwrite, "Replace a report already in --out");
  CLI::Option* bench_hardware =
      bench_cmd
          ->add_option("--hardware", bench.hardware_path,
                       "Hardware YAML: the real camera and arms (the object moved by hand, the "
                       "board where its bench section says), or data/config/hardware_sim.yaml "
                       "(the real drivers against simulated devices)")
          ->check(CLI::ExistingFile);
  bench_cmd
      ->add_option("--world", bench.world_config, "World YAML [data/config/world_default.yaml]")
      ->check(CLI::ExistingFile);
  bench_cmd->add_option("--object", bench.object,
                        "Object: a shipped name or a model path [the world's]");
  bench_cmd->add_option("--frames", bench.frames, "Camera frames")
      ->capture_default_str()
      ->check(aerograsp::cli::Range(1, 100000));
  bench_cmd->add_option("--seed", bench.seed, "World seed")
      ->capture_default_str()
      ->check(aerograsp::cli::Seed());
  aerograsp::AddTelemetryOptions(bench_cmd, &bench.telemetry);
  bench_cmd
      ->add_option(
          "--hover-m", bench.hover_m,
          "Servo to the grasp moved back this far along its approach (0: the grasp itself), m")
      ->capture_default_str()
      ->check(aerograsp::cli::Finite());
  bench_cmd
      ->add_option("--path-period", bench.path_period_s, "Period of the object's scripted path, s")
      ->capture_default_str()
      ->excludes(bench_hardware)
      ->check(aerograsp::cli::Range(1.0, 1000.0));
  bench_cmd
      ->add_option("--path-scale", bench.path_scale,
                   "Scale of the scripted path (1: +-6 cm fore and aft; 0: the object held still "
                   "at the grasp point)")
      ->capture_default_str()
      ->excludes(bench_hardware)
      ->check(aerograsp::cli::Finite());
  bench_cmd
      ->add_option(
          "--board-pose", bench_board_pose,
          "The tag board on the object, oMt: x y z (m) qw qx qy qz [centred on its top, face up]")
      ->expected(7)
      ->excludes(bench_hardware)
      ->check(aerograsp::cli::Finite());
  bench_cmd
      ->add_option(
          "--perception", bench.perception_config,
          "Perception YAML (see data/config/perception_default.yaml) [the mission config's]")
      ->check(CLI::ExistingFile);
  // ---- end bench ----

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  int code = aerograsp::kExitOk;
  try {
    if (*robot_cmd) aerograsp::RunRobotCommand(robot, std::cout);
    if (*record_cmd) aerograsp::RunRecordCommand(record, std::cout, std::cerr);
    if (*calibrate_cmd) aerograsp::RunCalibrateCommand(calibrate, std::cout, std::cerr);
    if (*render_bench_cmd) aerograsp::RunRenderBenchmark(render_bench, std::cout);
    if (*servo_bus_bench_cmd) aerograsp::RunServoBusBenchmark(servo_bus_bench, std::cout);
    if (*fault_bench_cmd) aerograsp::RunFaultBenchmark(fault_bench, std::cout);
    if (*mission_bench_cmd)
      code = aerograsp::RunMissionBenchmark(mission_bench, std::cout, std::cerr);
    if (*perception_bench_cmd)
      aerograsp::RunPerceptionBenchmark(perception_bench, std::cout, std::cerr);
    if (*hardware_check_cmd && aerograsp::RunHardwareCheck(hardware_check, std::cout) > 0)
      code = aerograsp::kExitError;
    if (*plan_cmd) {
      if (!plan_xyz.empty())
        plan.object_xyz_m = Eigen::Vector3d(plan_xyz[0], plan_xyz[1], plan_xyz[2]);
      if (!plan_rpy.empty())
        plan.object_rpy_deg = Eigen::Vector3d(plan_rpy[0], plan_rpy[1], plan_rpy[2]);
      aerograsp::RunPlanCommand(plan, std::cout);
    }
    if (*servo_benchmark_cmd) aerograsp::RunServoBenchmark(servo_benchmark, std::cout);
    if (*replay_cmd) {
      if (!replay_init.empty()) replay.init_cMo = aerograsp::PoseFromValues(replay_init);
      if (!replay_wMo.empty())
        replay.recording.wMo = aerograsp::PoseFromValues(replay_wMo, "--object-in-world");
      replay.recording.max_pair_gap_s = 1e-3 * replay_gap_ms;
      code = aerograsp::RunReplayCommand(replay, std::cout, std::cerr);
    }
    if (*convert_cmd) {
      if (!convert_wMo.empty())
        convert.recording.wMo = aerograsp::PoseFromValues(convert_wMo, "--object-in-world");
      convert.recording.max_pair_gap_s = 1e-3 * convert_gap_ms;
      aerograsp::RunConvertCommand(convert, std::cout, std::cerr);
    }
    if (*dataset_cmd) aerograsp::RunDatasetCommand(dataset, std::cout, std::cerr);
    if (*mission_cmd) code = aerograsp::RunMissionCommand(mission, std::cout, std::cerr);
    if (*import_cmd) aerograsp::RunObjectImport(object_import, std::cout);
    if (*show_cmd) aerograsp::RunObjectShow(object_show, object_show_folder, std::cout);
    if (*bench_cmd) {
      if (!bench_board_pose.empty())
        bench.oMt = aerograsp::PoseFromValues(bench_board_pose, "--board-pose");
      aerograsp::RunBenchCommand(bench, std::cout, std::cerr);
    }
  } catch (const std::exception& e) {
    std::cerr << "aerograsp: error: " << e.what() << "\n";
    return aerograsp::kExitError;
  }
  return code;
}
