// The reports' interactive charts: time series and a state timeline drawn in the
// browser by Chart.js (Debian's libjs-chart.js, built into the program and inlined
// into the page with our own script, app/report/report_charts.js), so a report
// folder works offline wherever it is copied. Each chart's data sits in the page as
// JSON next to its canvas, thinned out for long records (DecimateForChart). All
// charts of a page share one time axis: dragging across one zooms them all.
#pragma once

#include <cmath>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "app/report/plot_panel.h"

namespace aerograsp {

/// A vertical line across a chart at t_s (a grasp switch), `label` at its top (may be empty).
struct ChartMarker {
  double t_s = 0.0;
  std::string label;
};

/// One line of a TimeChart: a value per time of its chart, NaN for a gap.
struct ChartLine {
  std::string name;  ///< legend and tooltip
  std::vector<double> v;
  PlotColor color;
  int width_px = 1;
  bool stepped = false;  ///< holds each value until the next (found/lost)
};

/// Values over time, all lines sharing the times t_s (ascending).
struct TimeChart {
  std::string title;  ///< above the chart
  std::string unit;   ///< of the values, in tooltips ("m", "deg"); may be empty
  std::vector<double> t_s;
  std::vector<ChartLine> lines;
  std::vector<ChartMarker> markers;
  /// The value axis ends here when a value is higher (tooltips still give the value); NaN: no cut.
  double y_cut = NAN;
  /// Names for the values 0 and 1 on the value axis (e.g. {"lost", "found"}); empty: numbers.
  std::vector<std::string> value_names;
  int height_px = 170;
};

/// States over time, one row per machine.
struct TimelineChart {
  struct Bar {
    std::size_t row = 0, state = 0;  ///< indices into rows and states
    double t0_s = 0.0, t1_s = 0.0;
    std::string note;  ///< shown on hover: how the state was entered
  };
  std::string title;
  std::vector<std::string> rows;
  std::vector<std::string> states;
  std::vector<PlotColor> state_colors;  ///< one per state
  std::vector<Bar> bars;
  std::vector<ChartMarker> markers;
  double t0_s = 0.0, t1_s = 1.0;  ///< the time axis
};

/// A chart's JSON keeps every sample up to this many; past it, DecimateForChart thins it.
constexpr std::size_t kChartFullSamples = 1500;
/// Time buckets of a thinned chart, about one per 3 pixels of a page-wide chart.
constexpr std::size_t kChartBuckets = 300;

/// The sample indices a chart keeps (ascending): all of them up to kChartFullSamples samples;
/// else per time bucket (kChartBuckets of equal length) the first and last sample, each line's
/// lowest and highest, and where a line starts or ends a gap (NaN), so that peaks, steps and
/// gaps survive the thinning.
std::vector<std::size_t> DecimateForChart(const std::vector<double>& t_s,
                                          const std::vector<ChartLine>& lines);

/// A <div> with the chart's canvas and its data (JSON, decimated); every text is escaped.
void WriteHtmlTimeChart(const TimeChart& chart, std::ostream& html);
void WriteHtmlTimeline(const TimelineChart& chart, std::ostream& html);

/// A section's charts (`charts_html`, from the functions above) under a caption with a link to
/// `image`, the PNG of the same plot, which replaces the charts when the page is printed (an
/// empty `image`: there is none).
void WriteHtmlChartFigure(const std::string& charts_html, const std::string& image,
                          const std::string& caption, std::ostream& html);

/// Chart.js and the script that draws the page's charts, once at the end of a page with charts.
/// The script sets data-charts-drawn (the number of charts drawn) on <body> when done, and
/// data-charts-error (the message) if a chart could not be drawn.
void WriteHtmlChartScripts(std::ostream& html);

}  // namespace aerograsp
