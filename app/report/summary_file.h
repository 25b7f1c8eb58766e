// The machine-readable summary.json that commands write into their --out folder.
#pragma once

#include <string>

namespace aerograsp {

/// Creates `out_dir` and writes `json_text` (plus a newline) to out_dir/summary.json.
/// Returns the file's path. @throws std::runtime_error naming the file when it cannot be written.
std::string WriteSummaryFile(const std::string& out_dir, const std::string& json_text);

}  // namespace aerograsp
