#include "app/report/report_charts.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include "app/report/report_html.h"

namespace aerograsp {

// Generated at build time (app/CMakeLists.txt, cmake/EmbedText.cmake): Debian's chart.min.js
// (libjs-chart.js) and app/report/report_charts.js.
extern const char kChartJsSource[];
extern const char kReportChartsJsSource[];

namespace {

/// A JSON string that is safe inside <script>: no '<' (so no "</script>"), bad UTF-8 replaced.
std::string JsonString(const std::string& text) {
  const std::string json =
      nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

/// A value with 4 significant digits (0.1 mm of a metre, 0.1 deg of a hundred), null for NaN.
std::string JsonValue(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "null"; }

/// A time to 10 ms (a third of a camera frame), without trailing zeros.
std::string JsonTime(double t_s) {
  if (!std::isfinite(t_s)) return "null";
  std::string text = fmt::format("{:.2f}", t_s);
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text == "-0" ? "0" : text;
}

std::string JsonColor(const PlotColor& c) { return fmt::format("[{},{},{}]", c.r, c.g, c.b); }

std::string JsonMarkers(const std::vector<ChartMarker>& markers) {
  std::string out = "[";
  for (std::size_t k = 0; k < markers.size(); ++k) {
    out += fmt::format("{}{{\"t\":{},\"label\":{}}}", k ? "," : "", JsonTime(markers[k].t_s),
                       JsonString(markers[k].label));
  }
  return out + "]";
}

void WriteChartDiv(const std::string& title, const std::string& json, int height_px,
                   std::ostream& html) {
  html << "<div class=\"chart\" style=\"height:" << height_px
       << "px\"><canvas role=\"img\" aria-label=\"" << EscapeHtml(title)
       << "\"></canvas><script type=\"application/json\" class=\"chart-data\">" << json
       << "</script></div>\n";
}

}  // namespace

std::vector<std::size_t> DecimateForChart(const std::vector<double>& t_s,
                                          const std::vector<ChartLine>& lines) {
  const std::size_t n = t_s.size();
  std::vector<std::size_t> keep;
  if (n <= kChartFullSamples) {
    for (std::size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  const double t0_s = t_s.front(), span_s = std::max(t_s.back() - t0_s, 1e-9);
  auto bucket_of = [&](std::size_t i) {
    return std::min(kChartBuckets - 1,
                    std::size_t(std::max(0.0, (t_s[i] - t0_s) / span_s) * double(kChartBuckets)));
  };
  auto value = [](const ChartLine& line, std::size_t i) {
    return i < line.v.size() ? line.v[i] : NAN;
  };
  std::vector<std::size_t> lo(lines.size()), hi(lines.size());
  for (std::size_t first = 0, last = 0; first < n; first = last) {
    const std::size_t bucket = bucket_of(first);
    last = first + 1;
    while (last < n && bucket_of(last) == bucket) ++last;
    keep.push_back(first);
    keep.push_back(last - 1);
    for (std::size_t l = 0; l < lines.size(); ++l) {
      lo[l] = hi[l] = n;
      for (std::size_t i = first; i < last; ++i) {
        const double v = value(lines[l], i);
        if (i > 0 && std::isfinite(v) != std::isfinite(value(lines[l], i - 1))) {
          keep.push_back(i - 1);
          keep.push_back(i);
        }
        if (!std::isfinite(v)) continue;
        if (lo[l] == n || v < value(lines[l], lo[l])) lo[l] = i;
        if (hi[l] == n || v > value(lines[l], hi[l])) hi[l] = i;
      }
      if (lo[l] < n) keep.push_back(lo[l]);
      if (hi[l] < n) keep.push_back(hi[l]);
    }
  }
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  return keep;
}

void WriteHtmlTimeChart(const TimeChart& chart, std::ostream& html) {
  const std::vector<std::size_t> keep = DecimateForChart(chart.t_s, chart.lines);
  std::string json = fmt::format("{{\"kind\":\"time\",\"title\":{},\"unit\":{},\"t\":[",
                                 JsonString(chart.title), JsonString(chart.unit));
  for (std::size_t k = 0; k < keep.size(); ++k)
    json += (k ? "," : "") + JsonTime(chart.t_s[keep[k]]);
  json += "],\"lines\":[";
  for (std::size_t l = 0; l < chart.lines.size(); ++l) {
    const ChartLine& line = chart.lines[l];
    json += fmt::format("{}{{\"name\":{},\"color\":{},\"width\":{},\"stepped\":{},\"v\":[",
                        l ? "," : "", JsonString(line.name), JsonColor(line.color), line.width_px,
                        line.stepped ? "true" : "false");
    for (std::size_t k = 0; k < keep.size(); ++k)
      json += (k ? "," : "") + JsonValue(keep[k] < line.v.size() ? line.v[keep[k]] : NAN);
    json += "]}";
  }
  json += "],\"markers\":" + JsonMarkers(chart.markers);
  if (std::isfinite(chart.y_cut)) json += ",\"yCut\":" + JsonValue(chart.y_cut);
  if (!chart.value_names.empty()) {
    json += ",\"valueNames\":[";
    for (std::size_t k = 0; k < chart.value_names.size(); ++k)
      json += (k ? "," : "") + JsonString(chart.value_names[k]);
    json += "]";
  }
  WriteChartDiv(chart.title, json + "}", chart.height_px, html);
}

void WriteHtmlTimeline(const TimelineChart& chart, std::ostream& html) {
  std::string json =
      fmt::format("{{\"kind\":\"timeline\",\"title\":{},\"t0\":{},\"t1\":{},\"rows\":[",
                  JsonString(chart.title), JsonTime(chart.t0_s), JsonTime(chart.t1_s));
  for (std::size_t k = 0; k < chart.rows.size(); ++k)
    json += (k ? "," : "") + JsonString(chart.rows[k]);
  json += "],\"states\":[";
  for (std::size_t k = 0; k < chart.states.size(); ++k) {
    const PlotColor color = k < chart.state_colors.size() ? chart.state_colors[k] : PlotColor{};
    json +=
        fmt::format("{}{{\"name\":{},\"color\":{},\"text\":{}}}", k ? "," : "",
                    JsonString(chart.states[k]), JsonColor(color), JsonColor(TextColorOn(color)));
  }
  json += "],\"bars\":[";
  for (std::size_t k = 0; k < chart.bars.size(); ++k) {
    const TimelineChart::Bar& bar = chart.bars[k];
    json += fmt::format("{}[{},{},{},{},{}]", k ? "," : "", bar.row, bar.state, JsonTime(bar.t0_s),
                        JsonTime(bar.t1_s), JsonString(bar.note));
  }
  json += "],\"markers\":" + JsonMarkers(chart.markers) + "}";
  constexpr int kRowPx = 38, kAxesPx = 90;
  WriteChartDiv(chart.title, json, kAxesPx + kRowPx * int(chart.rows.size()), html);
}

void WriteHtmlChartFigure(const std::string& charts_html, const std::string& image,
                          const std::string& caption, std::ostream& html) {
  html << "<figure class=\"charts" << (image.empty() ? "" : " has-png") << "\"><figcaption>"
       << EscapeHtml(caption);
  if (!image.empty()) html << " <a href=\"" << EscapeHtml(image) << "\">PNG</a>";
  html << "</figcaption>\n" << charts_html;
  if (!image.empty()) {
    html << "<img class=\"print\" src=\"" << EscapeHtml(image) << "\" alt=\"" << EscapeHtml(caption)
         << "\">";
  }
  html << "</figure>\n";
}

void WriteHtmlChartScripts(std::ostream& html) {
  html << "<script>\n"
       << kChartJsSource << "\n</script>\n<script>\n"
       << kReportChartsJsSource << "\n</script>\n";
}

}  // namespace aerograsp
