// The replay's report page: DIR/index.html with the headline figures and the
// estimates over time as interactive charts (app/report/report_charts.h), beside
// pose_vs_truth.png (app/report/pose_plot.h) when the recording has a ground truth.
#pragma once

#include <string>
#include <vector>

#include "app/report/pose_plot.h"

namespace aerograsp {

/// Writes out_dir (which must exist)/index.html titled `title`: the `headline` rows (name,
/// value; escaped), then the charts of `estimates` against `truth` (PoseCharts). With truth
/// samples it also writes pose_vs_truth.png, linked from the page; without, the charts show
/// the estimates alone.
/// @throws std::runtime_error naming a file that could not be written.
void WriteReplayReport(const std::string& title,
                       const std::vector<std::vector<std::string>>& headline,
                       const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                       const std::string& out_dir);

}  // namespace aerograsp
