#include "app/commands/bench_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <sstream>

#include "app/report/mission_plots.h"
#include "app/report/plot_panel.h"
#include "app/report/pose_plot.h"
#include "app/report/report_charts.h"
#include "app/report/report_html.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "core/platform.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / M_PI;

nlohmann::json StatsJson(const BenchStats& s) {
  return {{"frames", s.t_err_m.size()},
          {"translation_rmse_m", BenchStats::Rms(s.t_err_m)},
          {"rotation_rmse_deg", BenchStats::Rms(s.r_err_deg)},
          {"translation_median_m", Percentile(s.t_err_m, 0.5, kNaN)},
          {"rotation_median_deg", Percentile(s.r_err_deg, 0.5, kNaN)}};
}

/// NaN (not finite) numbers become null, recursively.
void NullNonFinite(nlohmann::json* j) {
  if (j->is_number_float() && !std::isfinite(j->get<double>())) {
    *j = nullptr;
  } else if (j->is_object() || j->is_array()) {
    for (auto& v : *j) NullNonFinite(&v);
  }
}

const PlotColor kToTargetColor{200, 60, 30}, kToTruthColor{30, 140, 230};
constexpr double kServoErrorAxisCutM = 0.2;  // a lost target's metres would hide the millimetres

void WriteServoErrorPlot(const BenchServoTrace traces[2], const std::string& path) {
  constexpr int kWidth = 1200, kHeight = 220, kLeft = 80, kTop = 30, kGap = 50;
  cv::Mat image(kTop + 2 * (kHeight + kGap), kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  double t0 = std::numeric_limits<double>::infinity(), t1 = -t0;
  for (int a = 0; a < 2; ++a) ExpandRange(traces[a].t_s, &t0, &t1);
  if (!std::isfinite(t0) || t1 <= t0) t0 = 0.0, t1 = 1.0;
  for (int a = 0; a < 2; ++a) {
    double lo = 0.0, hi = 0.01;
    ExpandRange(traces[a].to_target_m, &lo, &hi);
    ExpandRange(traces[a].to_truth_m, &lo, &hi);
    hi = std::min(hi, kServoErrorAxisCutM);
    const PlotPanel panel{
        fmt::format("{} arm: tool to its target (m): to the commanded target blue, to the target "
                    "on the true object orange; gaps: no target",
                    SideName(kSides[a])),
        t0,
        t1,
        0.0,
        1.05 * hi,
        kLeft,
        kTop + a * (kHeight + kGap),
        kWidth - kLeft - 20,
        kHeight};
    DrawPanelAxes(&image, panel, "");
    DrawPanelSeries(&image, panel, traces[a].t_s, traces[a].to_truth_m, kToTruthColor, 1);
    DrawPanelSeries(&image, panel, traces[a].t_s, traces[a].to_target_m, kToTargetColor, 2);
    DrawPanelTimeLabels(&image, panel);
  }
  WritePlotPng(image, path);
}

/// The servo error plot as the page's charts: one per arm, gaps where there is no target.
std::vector<TimeChart> ServoErrorCharts(const BenchServoTrace traces[2]) {
  std::vector<TimeChart> charts;
  for (int a = 0; a < 2; ++a) {
    TimeChart chart;
    chart.title = fmt::format("{} arm: tool to its target (m)", SideName(kSides[a]));
    chart.unit = "m";
    chart.y_cut = kServoErrorAxisCutM;
    chart.t_s = traces[a].t_s;
    chart.lines = {{"to the commanded target", traces[a].to_target_m, kToTargetColor, 2},
                   {"to the target on the true object", traces[a].to_truth_m, kToTruthColor, 1}};
    if (std::none_of(chart.lines[1].v.begin(), chart.lines[1].v.end(),
                     [](double v) { return std::isfinite(v); }))
      chart.lines.pop_back();  // no truth (hardware)
    charts.push_back(std::move(chart));
  }
  return charts;
}

}  // namespace

void BenchStats::Add(const PoseError& e) {
  t_err_m.push_back(e.translation_m);
  r_err_deg.push_back(kRadToDeg * e.rotation_rad);
}

double BenchStats::Rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? kNaN : std::sqrt(s / v.size());
}

void AddBenchTrace(PoseTrace* trace, double t_s, bool ok, const Eigen::Isometry3d& cMo,
                   double rotation_error_deg) {
  trace->stamp_s.push_back(t_s);
  trace->x_m.push_back(ok ? cMo.translation().x() : kNaN);
  trace->y_m.push_back(ok ? cMo.translation().y() : kNaN);
  trace->z_m.push_back(ok ? cMo.translation().z() : kNaN);
  trace->rotation_error_deg.push_back(rotation_error_deg);
  trace->found.push_back(ok ? 1 : 0);
}

void WriteBenchReport(const BenchReportInfo& info, const BenchResults& run, std::ostream& out) {
  // summary.json
  const Eigen::Vector4d q_t = QuaternionWxyz(info.oMt);
  nlohmann::json summary;
  summary["object"] = info.object_name;
  summary["hardware"] = info.hardware;
  summary["seed"] = info.seed;
  summary["perception"] = info.perception;
  summary["frames"] = run.frames;
  summary["tag_frames"] = run.tag_frames;
  summary["found_frames"] = run.found_frames;
  summary["compared_frames"] = run.perception_vs_tags.t_err_m.size();
  summary["translation_rmse_m"] = BenchStats::Rms(run.perception_vs_tags.t_err_m);
  summary["rotation_rmse_deg"] = BenchStats::Rms(run.perception_vs_tags.r_err_deg);
  summary["translation_median_m"] = Percentile(run.perception_vs_tags.t_err_m, 0.5, kNaN);
  summary["rotation_median_deg"] = Percentile(run.perception_vs_tags.r_err_deg, 0.5, kNaN);
  summary["rotation_error"] =
      "perception vs tags: angle minimised over the object's rotational symmetries";
  summary["servo_target"] = info.hover_m > 0.0
                                ? fmt::format("hover {:.3f} m off the grasp", info.hover_m)
                                : std::string("the grasp");
  summary["hover_m"] = info.hover_m;
  summary["servo_error_m_median"] = Percentile(run.servo_error_tracking_m, 0.5, kNaN);
  summary["servo_error_m_p95"] = Percentile(run.servo_error_tracking_m, 0.95, kNaN);
  summary["servo_tracking_cycles"] = run.servo_error_tracking_m.size();
  summary["servo_error_m_median_all_cycles"] = Percentile(run.servo_error_all_m, 0.5, kNaN);
  summary["servo_error_definition"] =
      "distance from the tool point (measured joints) to its target (the estimated object times "
      "the planned grasp "
      "or hover point), over the servo cycles an arm tracks: from its first cycle within 0.01 m of "
      "the target "
      "until the grasp changes or the target is refused; _all_cycles counts every moving cycle";
  summary["servo_status_cycles"] = run.status_cycles;
  summary["grasp_plans"] = run.plans;
  summary["grasp_plans_without_grasp"] = run.no_grasp_plans;
  summary["grasp_switches"] = run.switches;
  summary["frame_ms_median"] = Percentile(run.frame_ms, 0.5, kNaN);
  summary["board"] = {{"family", info.board.family},
                      {"rows", info.board.rows},
                      {"cols", info.board.cols},
                      {"tag_size_m", info.board.tag_size_m},
                      {"spacing_m", info.board.spacing_m},
                      {"first_id", info.board.first_id},
                      {"oMt_xyz_qwxyz",
                       {info.oMt.translation().x(), info.oMt.translation().y(),
                        info.oMt.translation().z(), q_t[0], q_t[1], q_t[2], q_t[3]}}};
  summary["tags_vs_truth"] = StatsJson(run.tags_vs_truth);
  summary["perception_vs_truth"] = StatsJson(run.perception_vs_truth);
  summary["servo_error_to_truth_m_median"] = Percentile(run.servo_error_to_truth_m, 0.5, kNaN);
  NullNonFinite(&summary);
  WriteSummaryFile(info.out_dir, summary.dump(2));

  // The report.
  const fs::path dir(info.out_dir);
  const bool has_tags = run.tag_frames > 0;
  if (has_tags)
    WritePosePlot(run.tags_trace, {run.est_trace}, (dir / "pose_vs_tags.png").string(),
                  "cMo position");
  WriteServoErrorPlot(run.servo_traces, (dir / "servo_error.png").string());
  const bool has_joints = WriteMissionJointPlot(run.record, (dir / "joints.png").string());
  if (run.record.snapshot)
    WriteMissionCameraImage(*run.record.snapshot, info.object_mesh_o,
                            (dir / "camera.png").string());
  auto num = [&](const char* key, double scale, int decimals = 2) {
    return summary[key].is_number()
               ? fmt::format("{:.{}f}", scale * summary[key].get<double>(), decimals)
               : std::string("-");
  };
  std::ostringstream html;
  BeginHtmlPage("Bench report: " + info.object_name, html);
  WriteHtmlTable(
      {"result", "value"},
      {{"frames", std::to_string(run.frames)},
       {"frames with the board (tags)", std::to_string(run.tag_frames)},
       {"frames with the object found", std::to_string(run.found_frames)},
       {"perception vs tags: translation RMSE (mm)", num("translation_rmse_m", 1e3)},
       {"perception vs tags: rotation RMSE (deg)", num("rotation_rmse_deg", 1)},
       {"servo target", summary["servo_target"].get<std::string>()},
       {"servo error median while tracking (mm)", num("servo_error_m_median", 1e3)},
       {"servo error p95 while tracking (mm)", num("servo_error_m_p95", 1e3)},
       {"tags vs truth: translation RMSE (mm)",
        summary["tags_vs_truth"]["translation_rmse_m"].is_number()
            ? fmt::format("{:.2f}",
                          1e3 * summary["tags_vs_truth"]["translation_rmse_m"].get<double>())
            : "-"},
       {"hardware", info.hardware}},
      html);
  html << "<h2>Perception against the tags</h2>\n";
  if (has_tags) {
    std::ostringstream charts;
    for (const TimeChart& chart : PoseCharts(run.tags_trace, {run.est_trace}, "cMo position"))
      WriteHtmlTimeChart(chart, charts);
    WriteHtmlChartFigure(charts.str(), "pose_vs_tags.png",
                         "The object's position in the camera frame (cMo), from the tag board "
                         "(black) and from perception; perception's rotation error against the "
                         "tags (deg, over the object's symmetries) and whether it had the object.",
                         html);
  } else {
    html << "<p class=\"missing\">The board was never seen.</p>\n";
  }
  html << "<h2>Servo</h2>\n";
  {
    std::ostringstream charts;
    for (const TimeChart& chart : ServoErrorCharts(run.servo_traces))
      WriteHtmlTimeChart(chart, charts);
    WriteHtmlChartFigure(charts.str(), "servo_error.png",
                         "Each arm's tool point to its target (the planned grasp, or the hover "
                         "point off it) over time; gaps: no target.",
                         html);
  }
  if (has_joints) {
    std::ostringstream charts;
    WriteHtmlJointCharts(run.record, charts);
    WriteHtmlChartFigure(charts.str(), "joints.png",
                         "Joint targets (thin) vs measured positions (thick) of each arm, deg.",
                         html);
  } else {
    html << "<p class=\"missing\">No joint samples were recorded.</p>\n";
  }
  html << "<h2>Camera</h2>\n";
  WriteHtmlFigure(
      run.record.snapshot.has_value(), "camera.png",
      run.record.snapshot
          ? fmt::format("Camera frame at t = {:.2f} s: the detector box (green) and the object "
                        "model at the estimated pose cMo (cyan).",
                        run.record.snapshot->t_s)
          : std::string(),
      "No frame had both the board and the object.", html);
  WriteHtmlChartScripts(html);
  WriteHtmlPage(html.str(), info.out_dir);

  out << fmt::format("bench: {} frames, object {}, {}\n", run.frames, info.object_name,
                     info.hardware);
  out << fmt::format("  board seen in {} frames, object found in {}, both in {}\n", run.tag_frames,
                     run.found_frames, run.perception_vs_tags.t_err_m.size());
  out << fmt::format("  perception vs tags: translation RMSE {} mm, rotation RMSE {} deg\n",
                     num("translation_rmse_m", 1e3), num("rotation_rmse_deg", 1));
  if (run.tags_vs_truth.t_err_m.size()) {
    out << fmt::format("  tags vs truth: translation RMSE {:.2f} mm, rotation RMSE {:.3f} deg\n",
                       1e3 * BenchStats::Rms(run.tags_vs_truth.t_err_m),
                       BenchStats::Rms(run.tags_vs_truth.r_err_deg));
  }
  out << fmt::format(
      "  servo to {}: error median {} mm, p95 {} mm over {} tracking cycles ({} plans, {} without "
      "a grasp)\n",
      summary["servo_target"].get<std::string>(), num("servo_error_m_median", 1e3),
      num("servo_error_m_p95", 1e3), run.servo_error_tracking_m.size(), run.plans,
      run.no_grasp_plans);
}

}  // namespace aerograsp
