#include "app/report/plot_panel.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace aerograsp {
namespace {

cv::Scalar ToScalar(const PlotColor& c) { return cv::Scalar(c.b, c.g, c.r); }

constexpr double kTickLabelScale = 0.35;
const cv::Scalar kLabelGrey(60, 60, 60);

}  // namespace

PlotColor CategoryColor(std::size_t k) {
  // Kelly's first eleven colours of maximum contrast, then fifteen picked one by one, each the
  // farthest (CIELAB) from those before among moderate colours: any two differ by over 29 dE.
  static const PlotColor kColors[] = {
      {0, 195, 243},   {146, 86, 135},  {0, 132, 243},   {241, 202, 161}, {50, 0, 190},
      {128, 178, 194}, {130, 132, 132}, {86, 136, 0},    {172, 143, 230}, {165, 103, 0},
      {121, 147, 249}, {119, 238, 153}, {221, 238, 0},   {0, 136, 119},   {0, 85, 136},
      {255, 136, 119}, {119, 17, 187},  {255, 153, 255}, {170, 153, 0},   {68, 68, 153},
      {102, 221, 221}, {51, 102, 102},  {204, 221, 170}, {102, 187, 255}, {0, 119, 0},
      {204, 204, 238}};
  return kColors[k % (sizeof(kColors) / sizeof(kColors[0]))];
}

PlotColor TextColorOn(const PlotColor& background) {
  const double luma = 0.299 * background.r + 0.587 * background.g + 0.114 * background.b;
  return luma < 120.0 ? PlotColor{255, 255, 255} : PlotColor{0, 0, 0};
}

AxisTicks RoundTicks(double lo, double hi, int max_count) {
  AxisTicks ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi <= lo || max_count < 2) return ticks;
  auto count = [&](double step) {
    return std::floor(hi / step + 1e-9) - std::ceil(lo / step - 1e-9) + 1.0;
  };
  double step = std::pow(10.0, std::floor(std::log10((hi - lo) / max_count)));
  for (int k = 0; count(step) > max_count; k = (k + 1) % 3) step *= k == 1 ? 2.5 : 2.0;
  for (double i = std::ceil(lo / step - 1e-9); i <= std::floor(hi / step + 1e-9); i += 1.0)
    ticks.values.push_back(std::abs(i) < 0.5 ? 0.0 : i * step);
  ticks.decimals = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
  return ticks;
}

int PlotPanel::X(double t_s) const {
  const double f = (t_s - t0_s) / std::max(1e-9, t1_s - t0_s);
  return x0_px + int(f * width_px);
}

int PlotPanel::Y(double v) const {
  const double f = (v - lo) / std::max(1e-12, hi - lo);
  return y0_px + height_px - int(f * height_px);
}

void DrawPanelAxes(cv::Mat* image, const PlotPanel& panel, const std::string& unit) {
  const int x1 = panel.x0_px + panel.width_px;
  cv::putText(*image, panel.title, cv::Point(panel.x0_px, panel.y0_px - 8),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const AxisTicks ticks = RoundTicks(panel.lo, panel.hi, std::max(2, panel.height_px / 30));
  for (double v : ticks.values) {
    const int y = panel.Y(v);
    cv::line(*image, cv::Point(panel.x0_px, y), cv::Point(x1, y), cv::Scalar(225, 225, 225));
    cv::putText(*image, fmt::format("{:.{}f}{}", v, ticks.decimals, unit),
                cv::Point(panel.x0_px - kPlotValueLabelWidthPx, y + 4), cv::FONT_HERSHEY_SIMPLEX,
                kTickLabelScale, kLabelGrey, 1, cv::LINE_AA);
  }
  // The frame last, over the grid lines.
  cv::rectangle(*image, cv::Point(panel.x0_px, panel.y0_px),
                cv::Point(x1, panel.y0_px + panel.height_px), cv::Scalar(0, 0, 0));
}

void DrawPanelTimeLabels(cv::Mat* image, const PlotPanel& panel) {
  const int y1 = panel.y0_px + panel.height_px;
  const AxisTicks ticks = RoundTicks(panel.t0_s, panel.t1_s, std::max(2, panel.width_px / 90));
  for (double t_s : ticks.values) {
    const std::string text = fmt::format("{:.{}f} s", t_s, ticks.decimals);
    const int width =
        cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, kTickLabelScale, 1, nullptr).width;
    const int x = std::clamp(panel.X(t_s) - width / 2, 0, std::max(0, image->cols - width));
    cv::line(*image, cv::Point(panel.X(t_s), y1), cv::Point(panel.X(t_s), y1 + 4),
             cv::Scalar(0, 0, 0));
    cv::putText(*image, text, cv::Point(x, y1 + 16), cv::FONT_HERSHEY_SIMPLEX, kTickLabelScale,
                kLabelGrey, 1, cv::LINE_AA);
  }
}

void DrawPanelSeries(cv::Mat* image, const PlotPanel& panel, const std::vector<double>& t_s,
                     const std::vector<double>& v, const PlotColor& color, int thickness) {
  bool has_prev = false;
  cv::Point prev;
  for (std::size_t i = 0; i < t_s.size() && i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      has_prev = false;
      continue;
    }
    const cv::Point q(panel.X(t_s[i]), panel.Y(std::clamp(v[i], panel.lo, panel.hi)));
    if (has_prev) cv::line(*image, prev, q, ToScalar(color), thickness, cv::LINE_AA);
    prev = q;
    has_prev = true;
  }
}

void DrawPanelMarker(cv::Mat* image, const PlotPanel& panel, double t_s, const std::string& label,
                     const PlotColor& color) {
  const int x = panel.X(t_s);
  cv::line(*image, cv::Point(x, panel.y0_px), cv::Point(x, panel.y0_px + panel.height_px),
           ToScalar(color), 1, cv::LINE_AA);
  if (!label.empty()) {
    cv::putText(*image, label, cv::Point(x + 3, panel.y0_px + 12), cv::FONT_HERSHEY_SIMPLEX, 0.35,
                ToScalar(color), 1, cv::LINE_AA);
  }
}

void ExpandRange(const std::vector<double>& v, double* lo, double* hi) {
  for (double x : v) {
    if (std::isfinite(x)) {
      *lo = std::min(*lo, x);
      *hi = std::max(*hi, x);
    }
  }
}

void WritePlotPng(const cv::Mat& image, const std::string& path) {
  bool written = false;
  try {
    written = cv::imwrite(path, image);
  } catch (const cv::Exception&) {
    written = false;
  }
  if (!written) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace aerograsp
