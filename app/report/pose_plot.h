// The replay's plot (paper Fig. 12): estimate vs ground truth over time for the
// position x, y, z of cMo, the (symmetry-aware) rotation error, and the
// found/lost timeline; drawn with OpenCV into a PNG, and as the report page's
// interactive charts.
#pragma once

#include <string>
#include <vector>

#include "app/report/report_charts.h"

namespace aerograsp {

struct PoseTrace {
  std::string name;  ///< legend text
  std::vector<double> stamp_s;
  std::vector<double> x_m, y_m, z_m;       ///< NaN where there is no value
  std::vector<double> rotation_error_deg;  ///< NaN where there is no truth or no estimate
  std::vector<int> found;                  ///< 1 found, 0 lost (optional: may be empty)
};

/// `truth` (the reference, drawn black and named by its `name`: the ground
/// truth, or the tags on a bench) has positions only; every trace shares its time axis.
/// `position_label` names the plotted position in the panel titles, with its frames.
/// @throws std::runtime_error when the file cannot be written.
void WritePosePlot(const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                   const std::string& path, const std::string& position_label = "cMo position");

/// The same plot as five charts: x, y, z (m), the rotation error (deg; the axis cut at 30 deg
/// as in the PNG) and found/lost, the traces in the PNG's colours. A `truth` without samples
/// (a recording without ground truth) leaves out its lines and the rotation error.
std::vector<TimeChart> PoseCharts(const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                                  const std::string& position_label = "cMo position");

}  // namespace aerograsp
