#include "hardware/bag/recording.h"

#include <filesystem>

#include "hardware/bag/realsense_bag.h"
#include "hardware/tum_folder.h"

namespace aerograsp {
namespace fs = std::filesystem;

std::unique_ptr<RecordedCamera> OpenRecording(const std::string& path,
                                              const RecordingOptions& options) {
  const bool tum = IsTumFolder(path);
  if (!tum && (!options.intrinsics_file.empty() || options.wMo)) {
    throw HardwareError(path +
                        ": --intrinsics and --object-in-world apply to TUM RGB-D folders only "
                        "(sequences and .bag files carry their own calibration)");
  }
  if (fs::is_directory(path)) {
    if (fs::exists(fs::path(path) / "sequence.yaml")) {
      if (options.max_pair_gap_s > 0.0)
        throw HardwareError(path + ": --max-pair-gap does not apply to a sequence folder");
      return std::make_unique<ReplayCamera>(path);
    }
    if (tum) {
      TumOptions tum_options;
      if (!options.intrinsics_file.empty())
        tum_options.intrinsics = LoadIntrinsicsFile(options.intrinsics_file);
      tum_options.wMo = options.wMo;
      tum_options.max_pair_gap_s = options.max_pair_gap_s;
      return std::make_unique<TumCamera>(path, tum_options);
    }
    throw HardwareError(path +
                        ": not a recording (a sequence folder has sequence.yaml, a TUM RGB-D "
                        "folder rgb.txt and depth.txt; an unfinished recording?)");
  }
  if (fs::path(path).extension() == ".bag" || fs::is_regular_file(path)) {
    BagOptions bag;
    bag.max_pair_gap_s = options.max_pair_gap_s;
    return std::make_unique<RealsenseBagCamera>(path, bag);
  }
  throw HardwareError(path + ": no such file or folder");
}

}  // namespace aerograsp
