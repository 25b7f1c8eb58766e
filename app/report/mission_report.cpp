#include "app/report/mission_report.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "app/report/mission_plots.h"
#include "app/report/report_charts.h"
#include "app/report/report_html.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;

std::string Seconds(double t_s) { return fmt::format("{:.3f}", t_s); }

void WriteRunsTable(const std::vector<ReportRow>& runs, std::ostream& html) {
  std::vector<std::string> header;
  for (const auto& [column, value] : runs.front()) header.push_back(column);
  std::vector<std::vector<std::string>> rows;
  for (const ReportRow& run : runs) {
    rows.emplace_back();
    for (const auto& [column, value] : run) rows.back().push_back(value);
  }
  WriteHtmlTable(header, rows, html);
}

void WriteTransitionsTable(const MissionRecord& record, std::ostream& html) {
  std::vector<std::vector<std::string>> rows;
  for (const MissionTransition& tr : record.transitions) {
    rows.push_back({Seconds(tr.t_s), tr.machine, tr.from + " -> " + tr.to, tr.cause});
  }
  WriteHtmlTable({"time (s)", "machine", "from -> to", "cause"}, rows, html);
}

void WriteSwitchesTable(const MissionRecord& record, std::ostream& html) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < record.switches.size(); ++k) {
    const MissionGraspSwitch& sw = record.switches[k];
    rows.push_back({std::to_string(k + 1), Seconds(sw.t_s), std::to_string(sw.left_pair),
                    std::to_string(sw.right_pair), sw.reason});
  }
  WriteHtmlTable({"switch", "time (s)", "left pair", "right pair", "reason"}, rows, html);
}

}  // namespace

void WriteMissionReport(const MissionRecord& record, const TriangleMesh& object_mesh_o,
                        const ReportRow& headline, const std::vector<ReportRow>& runs,
                        const std::string& out_dir) {
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    throw std::runtime_error(out_dir + ": cannot create the report folder" +
                             (error ? " (" + error.message() + ")" : std::string()));
  }
  const fs::path dir(out_dir);
  const bool has_samples = !record.samples.empty();
  if (has_samples) WriteMissionPosePlot(record, (dir / "pose.png").string());
  const bool has_joints = WriteMissionJointPlot(record, (dir / "joints.png").string());
  const bool has_timeline = WriteMissionTimelinePlot(record, (dir / "timeline.png").string());
  if (record.snapshot)
    WriteMissionCameraImage(*record.snapshot, object_mesh_o, (dir / "camera.png").string());

  std::ostringstream html;
  BeginHtmlPage("Mission report: " + record.object_name, html);
  std::vector<std::vector<std::string>> headline_rows;
  for (const auto& [name, value] : headline) headline_rows.push_back({name, value});
  if (!headline_rows.empty()) WriteHtmlTable({"result", "value"}, headline_rows, html);

  html << "<h2>Object pose</h2>\n";
  if (has_samples) {
    std::ostringstream charts;
    for (const TimeChart& chart : MissionPoseCharts(record)) WriteHtmlTimeChart(chart, charts);
    WriteHtmlChartFigure(
        charts.str(), "pose.png",
        "The object's position in the body frame d (dto, m), estimate vs truth; the rotation "
        "error (deg, over the object's symmetries) and whether vision had the object; red lines "
        "mark the grasp switches.",
        html);
  } else {
    html << "<p class=\"missing\">No samples were recorded.</p>\n";
  }
  html << "<h2>Joints</h2>\n";
  if (has_joints) {
    std::ostringstream charts;
    WriteHtmlJointCharts(record, charts);
    WriteHtmlChartFigure(charts.str(), "joints.png",
                         "Joint targets (thin) vs measured positions (thick) of each arm, deg; "
                         "red lines mark the grasp switches, numbered as in the table below.",
                         html);
  } else {
    html << "<p class=\"missing\">No joint samples were recorded.</p>\n";
  }
  if (has_samples) {
    html << "<h2>Vehicle</h2>\n";
    std::ostringstream charts;
    for (const TimeChart& chart : MissionVehicleCharts(record)) WriteHtmlTimeChart(chart, charts);
    WriteHtmlChartFigure(charts.str(), "",
                         "The body's position in the world frame w (north, east, down, m) as the "
                         "autopilot reported it; red lines mark the grasp switches.",
                         html);
  }
  html << "<h2>State machines</h2>\n";
  if (const std::optional<TimelineChart> timeline = MissionTimelineChart(record)) {
    std::ostringstream chart;
    WriteHtmlTimeline(*timeline, chart);
    WriteHtmlChartFigure(chart.str(), "timeline.png",
                         "The state of each machine over time (hover a bar for why it was "
                         "entered); red lines mark the grasp switches.",
                         html);
  } else {
    html << "<p class=\"missing\">No state transitions were recorded.</p>\n";
  }
  html << "<h2>Camera</h2>\n";
  WriteHtmlFigure(
      record.snapshot.has_value(), "camera.png",
      record.snapshot
          ? fmt::format("Camera frame at t = {:.2f} s: the detector box (green) and the "
                        "object model at the estimated pose cMo (cyan).",
                        record.snapshot->t_s)
          : std::string(),
      "No camera snapshot was recorded.", html);
  if (!runs.empty()) {
    html << "<h2>Runs</h2>\n";
    WriteRunsTable(runs, html);
  }
  html << "<h2>Transitions</h2>\n";
  if (record.transitions.empty())
    html << "<p class=\"missing\">None.</p>\n";
  else
    WriteTransitionsTable(record, html);
  html << "<h2>Grasp switches</h2>\n";
  if (record.switches.empty())
    html << "<p class=\"missing\">None.</p>\n";
  else
    WriteSwitchesTable(record, html);
  if (has_samples || has_timeline) WriteHtmlChartScripts(html);
  WriteHtmlPage(html.str(), out_dir);
}

}  // namespace aerograsp
