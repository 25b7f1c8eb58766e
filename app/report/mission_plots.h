// The plots of the mission report (app/report/mission_report.h), each drawn with
// OpenCV into a PNG and, for the page, as interactive charts (app/report/report_charts.h).
// They share the mission's time axis: the span from the first to the last sample,
// transition or grasp switch.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/report/report_charts.h"
#include "app/runtime/mission_record.h"
#include "core/mesh.h"

namespace aerograsp {

/// The time span the record covers (0..1 s when it holds no time at all).
struct MissionSpan {
  double t0_s = 0.0, t1_s = 1.0;
};
MissionSpan ComputeMissionSpan(const MissionRecord& record);

/// The object's position in the body frame d, estimate vs truth, with the rotation error and
/// the found timeline (app/report/pose_plot.h).
/// @throws std::runtime_error "<path>: cannot be written".
void WriteMissionPosePlot(const MissionRecord& record, const std::string& path);

/// The pose plot's charts (PoseCharts) with the grasp switches marked; none without samples.
std::vector<TimeChart> MissionPoseCharts(const MissionRecord& record);

/// One chart per joint of `arm` (0 left, 1 right), degrees: target (thin) and actual (thick)
/// with the grasp switches marked; none when the arm has no joint values.
std::vector<TimeChart> MissionJointCharts(const MissionRecord& record, int arm);

/// The vehicle's body position in the world frame w (NED, m), one chart per axis, with the grasp
/// switches marked; none without samples. No PNG draws it.
std::vector<TimeChart> MissionVehicleCharts(const MissionRecord& record);

/// MissionJointCharts of both arms side by side, the left arm's on the left (narrow pages: above).
void WriteHtmlJointCharts(const MissionRecord& record, std::ostream& html);

/// The timeline plot's rows, states and colours as a chart whose bars tell, on hover, the cause
/// of each state's transition; nullopt without transitions.
std::optional<TimelineChart> MissionTimelineChart(const MissionRecord& record);

/// Joints of the arms, in degrees. The left arm's panels form the left column, the right arm's
/// the right; target thin, actual thick; the grasp switches are vertical lines numbered from 1.
/// Returns false (and writes nothing) when no sample holds a joint value.
/// @throws std::runtime_error "<path>: cannot be written".
bool WriteMissionJointPlot(const MissionRecord& record, const std::string& path);

/// One row per state machine ("global", "vehicle", "vision", "planner", "arms", then any other
/// machine in order of appearance), its states as coloured bars named when the name fits, and
/// a legend of the colours. Returns false (and writes nothing) without transitions.
/// @throws std::runtime_error "<path>: cannot be written".
bool WriteMissionTimelinePlot(const MissionRecord& record, const std::string& path);

/// The snapshot's frame with the detector box, the outline of `mesh_o` (object frame o) at the
/// estimated cMo (its silhouette and the creases of the faces towards the camera; edges with an
/// end behind the camera or closer than 1 cm to its plane are skipped), and the time in the
/// top-left corner.
/// @throws std::runtime_error "<path>: cannot be written".
void WriteMissionCameraImage(const MissionSnapshot& snapshot, const TriangleMesh& mesh_o,
                             const std::string& path);

}  // namespace aerograsp
