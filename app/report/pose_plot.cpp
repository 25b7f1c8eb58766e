#include "app/report/pose_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "app/report/plot_panel.h"

namespace aerograsp {
namespace {

constexpr int kWidth = 1200, kPanelHeight = 190, kLeft = 80, kRight = 20, kTop = 30, kGap = 40;

const PlotColor kColors[] = {{200, 60, 30}, {30, 140, 230}, {60, 170, 60}};
const PlotColor kBlack{0, 0, 0};
constexpr double kRotationAxisCutDeg = 30.0;
const char* const kAxes[] = {"x", "y", "z"};

const std::vector<double>& AxisOf(const PoseTrace& trace, int a) {
  return a == 0 ? trace.x_m : a == 1 ? trace.y_m : trace.z_m;
}

PlotPanel MakePanel(const std::string& title, double t0_s, double t1_s, double lo, double hi,
                    int y0_px) {
  return PlotPanel{title, t0_s, t1_s, lo, hi, kLeft, y0_px, kWidth - kLeft - kRight, kPanelHeight};
}

}  // namespace

void WritePosePlot(const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                   const std::string& path, const std::string& position_label) {
  const int panels = 5;
  cv::Mat img(kTop + panels * (kPanelHeight + kGap) + 20, kWidth, CV_8UC3,
              cv::Scalar(255, 255, 255));
  const double t0 = truth.stamp_s.empty() ? 0.0 : truth.stamp_s.front();
  const double t1 = truth.stamp_s.empty() ? 1.0 : truth.stamp_s.back();
  std::string names;
  for (std::size_t k = 0; k < estimates.size(); ++k) names += (k ? ", " : "") + estimates[k].name;
  for (int a = 0; a < 3; ++a) {
    auto pick = [a](const PoseTrace& tr) -> const std::vector<double>& { return AxisOf(tr, a); };
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    ExpandRange(pick(truth), &lo, &hi);
    for (const PoseTrace& e : estimates) ExpandRange(pick(e), &lo, &hi);
    if (!std::isfinite(lo)) lo = 0.0, hi = 1.0;
    const double pad = std::max(0.005, 0.1 * (hi - lo));
    const std::string title =
        fmt::format("{} {} (m): {} black, {}", position_label, kAxes[a], truth.name, names);
    const PlotPanel p =
        MakePanel(title, t0, t1, lo - pad, hi + pad, kTop + a * (kPanelHeight + kGap));
    DrawPanelAxes(&img, p, "");
    DrawPanelSeries(&img, p, truth.stamp_s, pick(truth), kBlack, 2);
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      DrawPanelSeries(&img, p, estimates[k].stamp_s, pick(estimates[k]), kColors[k % 3], 1);
    }
  }
  {
    double lo = 0.0, hi = 1.0;
    for (const PoseTrace& e : estimates) ExpandRange(e.rotation_error_deg, &lo, &hi);
    hi = std::min(hi, kRotationAxisCutDeg);
    const PlotPanel p = MakePanel("rotation error (deg, over the object's symmetries)", t0, t1, 0.0,
                                  hi * 1.1, kTop + 3 * (kPanelHeight + kGap));
    DrawPanelAxes(&img, p, "");
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      DrawPanelSeries(&img, p, estimates[k].stamp_s, estimates[k].rotation_error_deg,
                      kColors[k % 3], 1);
    }
  }
  {
    const PlotPanel p = MakePanel("found (1) / lost (0)", t0, t1, -0.2,
                                  1.2 + 0.1 * estimates.size(), kTop + 4 * (kPanelHeight + kGap));
    DrawPanelAxes(&img, p, "");
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      std::vector<double> v(estimates[k].found.begin(), estimates[k].found.end());
      for (double& x : v) x += 0.05 * k;
      DrawPanelSeries(&img, p, estimates[k].stamp_s, v, kColors[k % 3], 2);
    }
    DrawPanelTimeLabels(&img, p);
  }
  WritePlotPng(img, path);
}

std::vector<TimeChart> PoseCharts(const PoseTrace& truth, const std::vector<PoseTrace>& estimates,
                                  const std::string& position_label) {
  // Without a truth the first estimate gives the time axis.
  const bool has_truth = !truth.stamp_s.empty();
  const std::vector<double>& t_s =
      has_truth || estimates.empty() ? truth.stamp_s : estimates.front().stamp_s;
  std::vector<TimeChart> charts;
  for (int a = 0; a < 3; ++a) {
    TimeChart chart;
    chart.title = fmt::format("{} {} (m)", position_label, kAxes[a]);
    chart.unit = "m";
    chart.t_s = t_s;
    if (has_truth) chart.lines.push_back({truth.name, AxisOf(truth, a), kBlack, 2});
    for (std::size_t k = 0; k < estimates.size(); ++k)
      chart.lines.push_back({estimates[k].name, AxisOf(estimates[k], a), kColors[k % 3], 1});
    charts.push_back(std::move(chart));
  }
  if (has_truth) {
    TimeChart rotation;
    rotation.title = "rotation error (deg, over the object's symmetries)";
    rotation.unit = "deg";
    rotation.t_s = t_s;
    rotation.y_cut = kRotationAxisCutDeg;
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      rotation.lines.push_back(
          {estimates[k].name, estimates[k].rotation_error_deg, kColors[k % 3]});
    }
    charts.push_back(std::move(rotation));
  }
  TimeChart found;
  found.title = "found / lost";
  found.t_s = t_s;
  found.value_names = {"lost", "found"};
  found.height_px = 140;
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    if (estimates[k].found.empty()) continue;
    found.lines.push_back(
        {estimates[k].name,
         std::vector<double>(estimates[k].found.begin(), estimates[k].found.end()), kColors[k % 3],
         2, true});
  }
  if (!found.lines.empty()) charts.push_back(std::move(found));
  return charts;
}

}  // namespace aerograsp
