#include "app/commands/convert_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands/replay_command.h"
#include "app/report/progress.h"
#include "app/report/report_folder.h"
#include "hardware/sequence.h"

namespace aerograsp {

void RunConvertCommand(const ConvertCommandOptions& options, std::ostream& out,
                       std::ostream& progress) {
  ReportFolder folder(options.out_dir, options.overwrite, "sequence.yaml");
  const std::unique_ptr<RecordedCamera> input = OpenRecording(options.input, options.recording);
  SequenceInfo info = input->info();
  if (!options.object.empty()) info.object = options.object;
  const std::int64_t total = options.max_frames > 0
                                 ? std::min<std::int64_t>(options.max_frames, info.frame_count)
                                 : info.frame_count;

  SequenceWriter writer(folder.path(), info);
  Progress bar(progress, "convert", total, "frames");
  RgbdFrame frame;
  for (std::int64_t i = 0; i < total; ++i) {
    if (!input->Grab(&frame)) {
      throw HardwareError(
          fmt::format("{}: ended after {} of {} frames", options.input, i, info.frame_count));
    }
    SequenceExtras extras;
    if (input->has_groundtruth()) extras.cMo = input->extras(i).cMo;
    writer.Write(frame, extras);
    bar.Update(i + 1);
  }
  writer.Close();
  folder.Commit();
  bar.Finish();
  out << fmt::format("convert: {} frames of {} -> {}\n  {}\n  colour {}x{}, depth scale {} m{}\n",
                     total, options.input, options.out_dir, info.description, info.intrinsics.width,
                     info.intrinsics.height, info.depth_scale_m,
                     input->has_groundtruth() ? ", with ground truth" : "");
}

std::function<void()> AddRecordingOptions(CLI::App* cmd, RecordingOptions* o) {
  // Seven numbers and milliseconds on the command line, a pose and seconds once parsed.
  const auto wMo = std::make_shared<std::vector<double>>();
  const auto gap_ms = std::make_shared<double>(0.0);
  cmd->add_option("--intrinsics", o->intrinsics_file,
                  "TUM folders: colour intrinsics (ViSP camera XML or YAML)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--object-in-world", *wMo,
                  "TUM folders: the object in groundtruth.txt's world, x y z (m) qw qx qy qz "
                  "(gives the ground truth)")
      ->expected(7)
      ->check(cli::Finite());
  cmd->add_option("--max-pair-gap-ms", *gap_ms,
                  ".bag and TUM: pair colour and depth frames at most this far apart (ms) "
                  "[one depth frame period]")
      ->check(cli::Range(0.0, 1e6));
  return [o, wMo, gap_ms] {
    if (!wMo->empty()) o->wMo = PoseFromValues(*wMo, "--object-in-world");
    o->max_pair_gap_s = 1e-3 * *gap_ms;
  };
}

void AddConvertOptions(CLI::App* cmd, ConvertCommandOptions* o) {
  cmd->add_option("input", o->input, "RealSense .bag, TUM RGB-D or sequence folder")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out", o->out_dir, "Sequence folder to write")->required();
  cmd->add_option("--object", o->object,
                  "Object recorded in sequence.yaml (shipped name or model path)");
  cmd->add_option("--frames", o->max_frames, "At most this many frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", o->overwrite, "Replace a sequence already in --out");
  cmd->callback(AddRecordingOptions(cmd, &o->recording));
}

}  // namespace aerograsp
