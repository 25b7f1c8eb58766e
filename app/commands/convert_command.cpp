#include "app/commands/convert_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>

#include "app/report/progress.h"
#include "hardware/sequence.h"

namespace aerograsp {
namespace fs = std::filesystem;

void RunConvertCommand(const ConvertCommandOptions& options, std::ostream& out,
                       std::ostream& progress) {
  const fs::path target = fs::path(options.out_dir).lexically_normal();
  if (target.empty()) throw HardwareError("--out: no folder given");
  if (fs::exists(target) && (!fs::is_directory(target) || !fs::is_empty(target))) {
    if (!fs::exists(target / "sequence.yaml")) {
      throw HardwareError(options.out_dir +
                          ": exists and is not an empty folder or a sequence; choose another "
                          "folder");
    }
    if (!options.overwrite) {
      throw HardwareError(options.out_dir +
                          ": already holds a sequence; choose another folder or --overwrite");
    }
  }
  const std::unique_ptr<RecordedCamera> input = OpenRecording(options.input, options.recording);
  SequenceInfo info = input->info();
  if (!options.object.empty()) info.object = options.object;
  const std::int64_t total = options.max_frames > 0
                                 ? std::min<std::int64_t>(options.max_frames, info.frame_count)
                                 : info.frame_count;

  // Written beside the target and renamed when complete.
  const fs::path partial =
      target.parent_path() /
      fmt::format(".{}.partial-{}", target.filename().string(), static_cast<long>(getpid()));
  fs::remove_all(partial);
  try {
    SequenceWriter writer(partial.string(), info);
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
    bar.Finish();
    if (fs::exists(target)) fs::remove_all(target);
    fs::rename(partial, target);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(partial, ec);
    throw;
  }
  out << fmt::format("convert: {} frames of {} -> {}\n  {}\n  colour {}x{}, depth scale {} m{}\n",
                     total, options.input, options.out_dir, info.description, info.intrinsics.width,
                     info.intrinsics.height, info.depth_scale_m,
                     input->has_groundtruth() ? ", with ground truth" : "");
}

}  // namespace aerograsp
