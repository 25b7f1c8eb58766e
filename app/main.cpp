// The aerograsp command line.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "app/record_command.h"
#include "app/render_benchmark.h"
#include "app/robot_command.h"
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
  robot_cmd->add_option("--samples", robot.reach_samples,
                        "Random configurations sampled for the workspace figures")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  robot_cmd->add_option("--seed", robot.seed, "Seed of the workspace samples")->capture_default_str();
  robot_cmd->add_option("--plot", robot.plot_path,
                        "Write a PNG of the platform (side and front views, arms at home)");

  aerograsp::RecordCommandOptions record;
  CLI::App* record_cmd = app.add_subcommand(
      "record", "Simulate a hover in front of the object and write an RGB-D sequence with ground truth");
  record_cmd->add_option("--out", record.out_dir, "Sequence folder to create")->required();
  record_cmd->add_option("--frames", record.frames, "Number of frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  record_cmd->add_option("--seed", record.seed, "World seed (same seed, same sequence)")->capture_default_str();
  record_cmd->add_option("--world", record.world_config, "World YAML (default: data/config/world_default.yaml)")
      ->check(CLI::ExistingFile);
  record_cmd->add_option("--object", record.object, "Object: a shipped name (crawler, u_shape, pipe) or a model path");
  record_cmd->add_option("--motion", record.motion, "Object motion along the pipe")
      ->check(CLI::IsMember({"static", "crawl"}));
  record_cmd->add_flag("--overwrite", record.overwrite, "Replace a sequence already in --out");

  CLI::App* benchmark_cmd =
      app.add_subcommand("benchmark", "Speed and accuracy figures of one stage, printed and in DIR/summary.json");
  benchmark_cmd->require_subcommand(1);
  aerograsp::RenderBenchmarkOptions render_bench;
  CLI::App* render_bench_cmd =
      benchmark_cmd->add_subcommand("render", "Simulated D435 frame: ray casting and sensor model");
  render_bench_cmd->add_option("--out", render_bench.out_dir, "Folder for summary.json");
  render_bench_cmd->add_option("--frames", render_bench.frames, "Frames to render")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  render_bench_cmd->add_option("--seed", render_bench.seed, "World seed")->capture_default_str();
  render_bench_cmd->add_option("--world", render_bench.world_config, "World YAML")->check(CLI::ExistingFile);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (*robot_cmd) aerograsp::RunRobotCommand(robot, std::cout);
    if (*record_cmd) aerograsp::RunRecordCommand(record, std::cout, std::cerr);
    if (*render_bench_cmd) aerograsp::RunRenderBenchmark(render_bench, std::cout);
  } catch (const std::exception& e) {
    std::cerr << "aerograsp: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
