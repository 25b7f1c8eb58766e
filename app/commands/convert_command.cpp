#include "app/commands/convert_command.h"

#include <fmt/format.h>

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

}  // namespace aerograsp
