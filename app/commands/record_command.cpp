#include "app/commands/record_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "app/cli_checks.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "core/data_dir.h"
#include "hardware/sequence.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

/// Colour image and depth coloured by range (turbo map, black = no data).
void WritePreviews(const RgbdFrame& frame, double depth_scale_m, double max_range_m,
                   const std::string& folder) {
  const cv::Mat rgb(frame.color.height, frame.color.width, CV_8UC3,
                    const_cast<std::uint8_t*>(frame.color.data.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::string color_path = (fs::path(folder) / "preview_color.png").string();
  if (!cv::imwrite(color_path, bgr)) throw HardwareError(color_path + ": cannot be written");

  const cv::Mat depth(frame.depth.height, frame.depth.width, CV_16UC1,
                      const_cast<std::uint16_t*>(frame.depth.data.data()));
  cv::Mat scaled;
  depth.convertTo(scaled, CV_8UC1, 255.0 * depth_scale_m / max_range_m);
  cv::Mat coloured;
  cv::applyColorMap(scaled, coloured, cv::COLORMAP_TURBO);
  coloured.setTo(cv::Scalar(0, 0, 0), depth == 0);
  const std::string depth_path = (fs::path(folder) / "preview_depth.png").string();
  if (!cv::imwrite(depth_path, coloured)) throw HardwareError(depth_path + ": cannot be written");
}

}  // namespace

void RunRecordCommand(const RecordCommandOptions& options, std::ostream& out,
                      std::ostream& progress) {
  const std::string world_path =
      options.world_config.empty() ? DataPath("config/world_default.yaml") : options.world_config;
  WorldConfig config = WorldConfig::Load(world_path);
  if (!options.object.empty()) config.object.name = options.object;
  if (!options.motion.empty()) config.object.motion = options.motion;
  if (options.occlude_at_s >= 0.0) {
    config.occluder.enabled = true;
    config.occluder.start_s = options.occlude_at_s;
    config.occluder.duration_s = options.occlude_for_s;
    config.occluder.period_s = options.occlude_every_s;
  }
  config.Validate(config.source, "");
  if (options.frames < 1) throw HardwareError("--frames: must be at least 1");
  ReportFolder folder(options.out_dir, options.overwrite, "sequence.yaml");

  World world(config, options.seed);
  SimCamera camera(&world);
  SequenceInfo info;
  info.intrinsics = camera.intrinsics();
  info.depth_scale_m = camera.depth_scale_m();
  // What finds the object again: its name, or the absolute path of its file
  // (`replay` then needs no --object).
  info.object = world.object().reference;
  info.frame_rate_hz = config.camera.frame_rate_hz;
  info.description =
      fmt::format("aerograsp simulator, world {}, seed {}, object {} ({})", world_path,
                  options.seed, world.object().name, config.object.motion);
  SequenceWriter writer(folder.path(), info);

  Progress bar(progress, "record", options.frames, "frames");
  double render_s = 0.0, raycast_s = 0.0, model_s = 0.0, valid_depth = 0.0, object_pixels = 0.0;
  RgbdFrame frame;
  for (int i = 0; i < options.frames; ++i) {
    world.StepTo(i / config.camera.frame_rate_hz);
    const auto t0 = std::chrono::steady_clock::now();
    camera.Grab(&frame);
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    raycast_s += camera.last_render_s();
    model_s += camera.last_sensor_model_s();
    SequenceExtras extras;
    extras.cMo = world.wMc().inverse() * world.wMo();
    extras.vehicle = world.vehicle().State();
    extras.q_left_rad = world.arm(Side::kLeft).q_measured_rad();
    extras.q_right_rad = world.arm(Side::kRight).q_measured_rad();
    writer.Write(frame, extras);
    if (i == 0)
      WritePreviews(frame, info.depth_scale_m, config.camera.d435.max_range_m, folder.path());
    valid_depth += std::count_if(frame.depth.data.begin(), frame.depth.data.end(),
                                 [](std::uint16_t d) { return d != 0; }) /
                   static_cast<double>(frame.depth.data.size());
    const auto& ids = camera.last_truth().object_id.data;
    object_pixels += std::count(ids.begin(), ids.end(), camera.object_render_id());
    bar.Update(i + 1);
  }
  writer.Close();
  folder.Commit();
  bar.Finish();
  const int n = options.frames;
  out << fmt::format(
      "sequence: {}\n"
      "  {} frames at {} Hz ({:.2f} s simulated), object {} ({}), seed {}\n"
      "  camera frame: {:.1f} ms (ray casting {:.1f} ms, D435 model {:.1f} ms); depth valid on "
      "{:.1f} % of pixels; "
      "object on {:.0f} pixels per frame on average\n"
      "  previews: {}/preview_color.png, preview_depth.png\n",
      options.out_dir, n, config.camera.frame_rate_hz, (n - 1) / config.camera.frame_rate_hz,
      world.object().name, config.object.motion, options.seed, 1e3 * render_s / n,
      1e3 * raycast_s / n, 1e3 * model_s / n, 100.0 * valid_depth / n, object_pixels / n,
      options.out_dir);
}

void AddRecordOptions(CLI::App* cmd, RecordCommandOptions* o) {
  cmd->add_option("--out", o->out_dir, "Sequence folder to create")->required();
  cmd->add_option("--frames", o->frames, "Number of frames")
      ->capture_default_str()
      ->check(cli::Range(1, 1000000));
  cmd->add_option("--seed", o->seed, "World seed (same seed, same sequence)")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--world", o->world_config,
                  "World YAML (default: data/config/world_default.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--object", o->object,
                  "Object: a shipped name (crawler, u_shape, pipe) or a model path");
  cmd->add_option("--motion", o->motion, "Object motion along the pipe")
      ->check(CLI::IsMember({"static", "crawl"}));
  cmd->add_flag("--overwrite", o->overwrite, "Replace a sequence already in --out");
  cmd->add_option("--occlude-at", o->occlude_at_s,
                  "A panel hides the object fully from this simulated time on, s (off by default)")
      ->check(cli::Range(0.0, 1e6));
  cmd->add_option("--occlude-for", o->occlude_for_s, "How long the panel hides the object, s")
      ->capture_default_str()
      ->check(cli::Range(1e-3, 1e6));
  cmd->add_option("--occlude-every", o->occlude_every_s,
                  "The panel hides the object again every this many seconds (0: once)")
      ->capture_default_str()
      ->check(cli::Range(0.0, 1e6));
}

}  // namespace aerograsp
