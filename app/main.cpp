// The aerograsp command line.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "app/robot_command.h"
#include "app/servo_benchmark.h"
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

  // --- benchmark: speed and accuracy figures of one stage ---
  CLI::App* benchmark_cmd =
      app.add_subcommand("benchmark", "Speed and accuracy figures of one stage, printed and in summary.json");
  benchmark_cmd->require_subcommand(1);
  aerograsp::ServoBenchmarkOptions servo_benchmark;
  CLI::App* servo_benchmark_cmd = benchmark_cmd->add_subcommand(
      "servo", "Dual-arm servo: convergence, iterations, step time, safe-volume entries; KDL IK on the same targets");
  aerograsp::AddServoBenchmarkOptions(servo_benchmark_cmd, &servo_benchmark);
  // --- end benchmark ---

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (*robot_cmd) aerograsp::RunRobotCommand(robot, std::cout);
    if (*servo_benchmark_cmd) aerograsp::RunServoBenchmark(servo_benchmark, std::cout);
  } catch (const std::exception& e) {
    std::cerr << "aerograsp: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
