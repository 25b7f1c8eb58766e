#include "app/report/replay_report.h"

#include <filesystem>
#include <sstream>

#include "app/report/report_charts.h"
#include "app/report/report_html.h"

namespace aerograsp {

void WriteReplayReport(const std::string& title,
                       const std::vector<std::vector<std::string>>& headline,
                       const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                       const std::string& out_dir) {
  const bool has_truth = !truth.stamp_s.empty();
  const std::string image = has_truth ? "pose_vs_truth.png" : "";
  if (has_truth) WritePosePlot(truth, estimates, (std::filesystem::path(out_dir) / image).string());
  std::ostringstream html;
  BeginHtmlPage(title, html);
  WriteHtmlTable({"result", "value"}, headline, html);
  html << "<h2>Object pose</h2>\n";
  std::ostringstream charts;
  for (const TimeChart& chart : PoseCharts(truth, estimates)) WriteHtmlTimeChart(chart, charts);
  WriteHtmlChartFigure(charts.str(), image,
                       has_truth ? "The object's position in the camera frame (cMo, m), each "
                                   "estimate against the recording's ground truth (black); the "
                                   "rotation error (deg, over the object's symmetries) and "
                                   "whether each tracker had the object."
                                 : "The object's position in the camera frame (cMo, m) as each "
                                   "tracker estimated it (the recording has no ground truth) and "
                                   "whether it had the object.",
                       html);
  WriteHtmlChartScripts(html);
  WriteHtmlPage(html.str(), out_dir);
}

}  // namespace aerograsp
