// The aerograsp command line.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "app/benchmarks/fault_benchmark.h"
#include "app/benchmarks/mission_benchmark.h"
#include "app/benchmarks/perception_benchmark.h"
#include "app/benchmarks/render_benchmark.h"
#include "app/benchmarks/servo_benchmark.h"
#include "app/benchmarks/servo_bus_benchmark.h"
#include "app/calibration/calibrate_command.h"
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
#include "app/exit_codes.h"

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
  CLI::App* robot_cmd = app.add_subcommand(
      "robot", "Print the platform: frame tree, camera, safe volume, arm chains, limits, reach");
  aerograsp::AddRobotOptions(robot_cmd, &robot);

  aerograsp::RecordCommandOptions record;
  CLI::App* record_cmd = app.add_subcommand(
      "record",
      "Simulate a hover in front of the object and write an RGB-D sequence with ground truth");
  aerograsp::AddRecordOptions(record_cmd, &record);

  CLI::App* benchmark_cmd = app.add_subcommand(
      "benchmark", "Speed and accuracy figures of one stage, printed and in DIR/summary.json");
  benchmark_cmd->require_subcommand(1);
  aerograsp::RenderBenchmarkOptions render_bench;
  CLI::App* render_bench_cmd =
      benchmark_cmd->add_subcommand("render", "Simulated D435 frame: ray casting and sensor model");
  aerograsp::AddRenderBenchmarkOptions(render_bench_cmd, &render_bench);
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
  aerograsp::AddServoBusBenchmarkOptions(servo_bus_bench_cmd, &servo_bus_bench);
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
  aerograsp::AddPerceptionBenchmarkOptions(perception_bench_cmd, &perception_bench);
  // ---- end benchmark perception ----
  // ---- hardware-check: open each device of a hardware config ----
  aerograsp::HardwareCheckOptions hardware_check;
  CLI::App* hardware_check_cmd = app.add_subcommand(
      "hardware-check",
      "Open each device of a hardware configuration and report it (nothing moves)");
  aerograsp::AddHardwareCheckOptions(hardware_check_cmd, &hardware_check);
  // ---- end hardware-check ----
  // ---- plan: dual grasps of an object ----
  aerograsp::PlanCommandOptions plan;
  CLI::App* plan_cmd = app.add_subcommand(
      "plan",
      "Rank the dual grasps of an object (shipped name or mesh path); table, PNG, summary.json");
  aerograsp::AddPlanOptions(plan_cmd, &plan);
  // ---- end plan ----

  aerograsp::CalibrateCommandOptions calibrate;
  CLI::App* calibrate_cmd = app.add_subcommand("calibrate",
                                               "Camera-to-arm calibration from an AprilTag board "
                                               "on the gripper, or the camera's intrinsics");
  aerograsp::AddCalibrateOptions(calibrate_cmd, &calibrate);
  // ---- replay and dataset: perception ----
  aerograsp::ReplayCommandOptions replay;
  CLI::App* replay_cmd = app.add_subcommand("replay",
                                            "Run perception on a recorded sequence: poses.csv, "
                                            "summary.json, plots; ViSP's tracker beside it");
  aerograsp::AddReplayOptions(replay_cmd, &replay);
  aerograsp::ConvertCommandOptions convert;
  CLI::App* convert_cmd = app.add_subcommand(
      "convert", "Write a RealSense .bag or a TUM RGB-D folder as a sequence folder");
  aerograsp::AddConvertOptions(convert_cmd, &convert);

  aerograsp::DatasetCommandOptions dataset;
  CLI::App* dataset_cmd = app.add_subcommand(
      "dataset",
      "Render labelled detector training images of an object (160x120 PNG + labels.csv)");
  aerograsp::AddDatasetOptions(dataset_cmd, &dataset);
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
  CLI::App* object_cmd =
      app.add_subcommand("object", "Bring in a user's object (import) and describe one (show)");
  object_cmd->require_subcommand(1);
  aerograsp::ObjectImportOptions object_import;
  CLI::App* import_cmd = object_cmd->add_subcommand(
      "import",
      "Check, repair and measure a mesh (PLY, OBJ, STL, ViSP .cao; mass, symmetry) and store it "
      "as an object every command finds by name (docs/objects.md)");
  aerograsp::AddObjectImportOptions(import_cmd, &object_import);
  aerograsp::ObjectShowOptions object_show;
  CLI::App* show_cmd = object_cmd->add_subcommand(
      "show", "Where an object is and what it is (mesh, mass, symmetry, detector)");
  aerograsp::AddObjectShowOptions(show_cmd, &object_show);
  // ---- end object import ----
  // ---- bench: perception and servo against tags on a test stand ----
  aerograsp::BenchCommandOptions bench;
  CLI::App* bench_cmd =
      app.add_subcommand("bench",
                         "Vehicle on a test stand, the object with a tag board moved by script "
                         "(simulator) or by hand (--hardware): perception against the tags, "
                         "servo error to the grasp or a hover point off it; report in DIR");
  aerograsp::AddBenchOptions(bench_cmd, &bench);
  // ---- end bench ----

  int code = aerograsp::kExitOk;
  try {
    try {
      app.parse(argc, argv);  // the commands' callbacks turn raw numbers into poses
    } catch (const CLI::ParseError& e) {
      return app.exit(e);
    }
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
    if (*plan_cmd) aerograsp::RunPlanCommand(plan, std::cout);
    if (*servo_benchmark_cmd) aerograsp::RunServoBenchmark(servo_benchmark, std::cout);
    if (*replay_cmd) code = aerograsp::RunReplayCommand(replay, std::cout, std::cerr);
    if (*convert_cmd) aerograsp::RunConvertCommand(convert, std::cout, std::cerr);
    if (*dataset_cmd) aerograsp::RunDatasetCommand(dataset, std::cout, std::cerr);
    if (*mission_cmd) code = aerograsp::RunMissionCommand(mission, std::cout, std::cerr);
    if (*import_cmd) aerograsp::RunObjectImport(object_import, std::cout);
    if (*show_cmd) aerograsp::RunObjectShow(object_show.object, object_show.folder_only, std::cout);
    if (*bench_cmd) aerograsp::RunBenchCommand(bench, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "aerograsp: error: " << e.what() << "\n";
    return aerograsp::kExitError;
  }
  return code;
}
