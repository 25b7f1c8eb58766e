// The drawing pieces the app's time plots share (app/report/pose_plot.cpp,
// app/report/mission_report.cpp): a panel maps (time, value) to pixels, draws its
// frame with value grid lines at round numbers, series that break at NaN, marker
// lines at given times and time labels. OpenCV stays in the .cpp: images cross
// this header as cv::Mat pointers.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace cv {
class Mat;
}

namespace aerograsp {

/// A colour as OpenCV draws it: blue, green, red, 0..255.
struct PlotColor {
  int b = 0, g = 0, r = 0;
};

/// The k-th (from 0) of a set of colours for categories (states): the first 26 are clearly
/// distinct from one another, later ones repeat them.
PlotColor CategoryColor(std::size_t k);

/// Black, or white where `background` is too dark for black text to be read on it.
PlotColor TextColorOn(const PlotColor& background);

/// Axis ticks at round numbers: the multiples of 1, 2 or 5 times a power of ten that lie in
/// [lo, hi], spaced so that there are between 3 and about `max_count` of them (fewer when the
/// range is empty or not finite).
struct AxisTicks {
  std::vector<double> values;
  int decimals = 0;  ///< digits after the point that print every tick exactly
};
AxisTicks RoundTicks(double lo, double hi, int max_count = 6);

/// A rectangle of an image that shows values lo..hi over times t0_s..t1_s.
struct PlotPanel {
  std::string title;  ///< written above the frame
  double t0_s = 0.0, t1_s = 1.0;
  double lo = 0.0, hi = 1.0;
  int x0_px = 0, y0_px = 0;  ///< top-left corner of the frame
  int width_px = 0, height_px = 0;

  /// Pixel column of time t_s (not clamped).
  int X(double t_s) const;
  /// Pixel row of value v (not clamped; larger values are higher up).
  int Y(double v) const;
};

/// Left of the frame the value labels need this much room, pixels.
constexpr int kPlotValueLabelWidthPx = 76;

/// The frame, the title, value grid lines at round numbers (RoundTicks) and their labels
/// (then `unit`) left of the frame.
void DrawPanelAxes(cv::Mat* image, const PlotPanel& panel, const std::string& unit);

/// Time ticks and labels (s) under the frame at round numbers (RoundTicks).
void DrawPanelTimeLabels(cv::Mat* image, const PlotPanel& panel);

/// The polyline (t_s[i], v[i]), values clamped to the panel, broken where v is NaN.
void DrawPanelSeries(cv::Mat* image, const PlotPanel& panel, const std::vector<double>& t_s,
                     const std::vector<double>& v, const PlotColor& color, int thickness);

/// A vertical line at t_s across the frame, `label` (may be empty) at its top.
void DrawPanelMarker(cv::Mat* image, const PlotPanel& panel, double t_s, const std::string& label,
                     const PlotColor& color);

/// Widens [*lo, *hi] to hold the finite values of v.
void ExpandRange(const std::vector<double>& v, double* lo, double* hi);

/// Writes the image as a PNG.
/// @throws std::runtime_error "<path>: cannot be written".
void WritePlotPng(const cv::Mat& image, const std::string& path);

}  // namespace aerograsp
