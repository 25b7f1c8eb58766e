// The mission's report: a folder with index.html and its PNG plots, drawn
// from a MissionRecord (app/runtime/mission_record.h). The page shows the time
// series as interactive charts (app/report/report_charts.h) and links the PNGs,
// which replace the charts in print. Opens in a browser with no network: the
// chart library is inlined, the images sit next to the page.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "app/runtime/mission_record.h"
#include "core/mesh.h"

namespace aerograsp {

/// One table row: (column or name, value text).
using ReportRow = std::vector<std::pair<std::string, std::string>>;

/// Writes out_dir/index.html (created with its parents when missing) and the plots it shows:
/// - pose.png: the object's position in the body frame d, estimate vs truth, the rotation
///   error and the found timeline (app/report/pose_plot.h); needs samples.
/// - joints.png: per arm and joint, target (thin) vs actual (thick), degrees, with the grasp
///   switches marked; needs samples with joints.
/// - timeline.png: one row per state machine, its states as coloured bars; needs transitions.
/// - camera.png: the snapshot with the detector box and `object_mesh_o` (object frame o,
///   metres) drawn at the estimated cMo; needs a snapshot.
/// The page draws pose, joints, the vehicle's position and the timeline as interactive charts with
/// the same data (decimated for long missions) and links each PNG. A plot without its data is not
/// written and the page says so. `headline` rows (name, value) form the table at the top; `runs`
/// (may be empty) holds one row per seeded run, every row with the same columns in the same order.
/// Every text is HTML-escaped.
/// @throws std::runtime_error naming the folder or file that could not be written.
void WriteMissionReport(const MissionRecord& record, const TriangleMesh& object_mesh_o,
                        const ReportRow& headline, const std::vector<ReportRow>& runs,
                        const std::string& out_dir);

}  // namespace aerograsp
