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

}  // namespace

int PlotPanel::X(double t_s) const {
  const double f = (t_s - t0_s) / std::max(1e-9, t1_s - t0_s);
  return x0_px + int(f * width_px);
}

int PlotPanel::Y(double v) const {
  const double f = (v - lo) / std::max(1e-12, hi - lo);
  return y0_px + height_px - int(f * height_px);
}

void DrawPanelAxes(cv::Mat* image, const PlotPanel& panel, const std::string& unit, int decimals) {
  const int x1 = panel.x0_px + panel.width_px;
  cv::putText(*image, panel.title, cv::Point(panel.x0_px, panel.y0_px - 8),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  for (int k = 0; k <= 4; ++k) {
    double v = panel.lo + (panel.hi - panel.lo) * k / 4.0;
    const int y = panel.Y(v);
    if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;  // no "-0.0"
    cv::line(*image, cv::Point(panel.x0_px, y), cv::Point(x1, y), cv::Scalar(225, 225, 225));
    cv::putText(*image, fmt::format("{:.{}f}{}", v, decimals, unit),
                cv::Point(panel.x0_px - kPlotValueLabelWidthPx, y + 4), cv::FONT_HERSHEY_SIMPLEX,
                0.35, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  }
  // The frame last, over the grid lines at lo and hi.
  cv::rectangle(*image, cv::Point(panel.x0_px, panel.y0_px),
                cv::Point(x1, panel.y0_px + panel.height_px), cv::Scalar(0, 0, 0));
}

void DrawPanelTimeLabels(cv::Mat* image, const PlotPanel& panel) {
  for (int k = 0; k <= 4; ++k) {
    const double t_s = panel.t0_s + (panel.t1_s - panel.t0_s) * k / 4.0;
    const std::string text = fmt::format("{:.1f} s", t_s);
    const int width = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.35, 1, nullptr).width;
    const int x = std::clamp(panel.X(t_s) - width / 2, 0, std::max(0, image->cols - width));
    cv::putText(*image, text, cv::Point(x, panel.y0_px + panel.height_px + 14),
                cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
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
