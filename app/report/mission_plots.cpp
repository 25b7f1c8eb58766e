#include "app/report/mission_plots.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <utility>
#include <vector>

#include "app/report/plot_panel.h"
#include "app/report/pose_plot.h"

namespace aerograsp {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr int kRightMarginPx = 20;
const PlotColor kSwitchColor{40, 40, 220};
const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrey(110, 110, 110);

cv::Mat WhiteCanvas(int width_px, int height_px) {
  return cv::Mat(height_px, width_px, CV_8UC3, kWhite);
}

void PutText(cv::Mat* image, const std::string& text, int x_px, int y_px, double scale,
             const cv::Scalar& color) {
  cv::putText(*image, text, cv::Point(x_px, y_px), cv::FONT_HERSHEY_SIMPLEX, scale, color, 1,
              cv::LINE_AA);
}

int TextWidth(const std::string& text, double scale) {
  return cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, nullptr).width;
}

// ---- joints ----

constexpr int kJointColumnWidthPx = 700, kJointPanelHeightPx = 120, kJointGapPx = 46,
              kJointTopPx = 56;
const PlotColor kTargetColor{30, 140, 230}, kActualColor{200, 60, 30};
const PlotColor kVehicleColor{60, 130, 40};

int ArmDof(const MissionRecord& record, int arm) {
  std::size_t dof = record.joint_names[arm].size();
  for (const MissionSample& s : record.samples) {
    dof = std::max(
        {dof, std::size_t(s.q_target_rad[arm].size()), std::size_t(s.q_actual_rad[arm].size())});
  }
  return int(dof);
}

/// Joint `joint` of `arm` at every sample, degrees; NaN where the sample has no such joint.
std::vector<double> JointSeriesDeg(const MissionRecord& record, int arm, int joint, bool target) {
  std::vector<double> v_deg;
  v_deg.reserve(record.samples.size());
  for (const MissionSample& s : record.samples) {
    const Eigen::VectorXd& q_rad = target ? s.q_target_rad[arm] : s.q_actual_rad[arm];
    v_deg.push_back(joint < q_rad.size() ? q_rad[joint] * kRadToDeg : NAN);
  }
  return v_deg;
}

std::string JointName(const MissionRecord& record, int arm, int joint) {
  return joint < int(record.joint_names[arm].size()) ? record.joint_names[arm][joint]
                                                     : fmt::format("joint {}", joint + 1);
}

// ---- timeline ----

constexpr int kTimelineWidthPx = 1200, kRowHeightPx = 34, kRowGapPx = 12, kNameWidthPx = 100,
              kTimelineTopPx = 34;
constexpr double kBarTextScale = 0.42;
const char* const kMachines[] = {"global", "vehicle", "vision", "planner", "arms"};

void AddOnce(const std::string& name, std::vector<std::string>* names) {
  if (std::find(names->begin(), names->end(), name) == names->end()) names->push_back(name);
}

/// Each state its own colour, in order of first appearance (CategoryColor).
PlotColor StateColor(const std::vector<std::string>& states, const std::string& state) {
  return CategoryColor(std::find(states.begin(), states.end(), state) - states.begin());
}

cv::Scalar ToScalar(const PlotColor& c) { return cv::Scalar(c.b, c.g, c.r); }

/// A state a machine was in from t0_s to t1_s, entered for `cause` (empty for the first).
struct StateBar {
  std::string state;
  double t0_s, t1_s;
  std::string cause;
};

/// The timeline's rows (kMachines, then any other machine in order of appearance) and its
/// states in order of appearance (which gives their colours).
void MachinesAndStates(const MissionRecord& record, std::vector<std::string>* machines,
                       std::vector<std::string>* states) {
  machines->assign(std::begin(kMachines), std::end(kMachines));
  states->clear();
  for (const MissionTransition& tr : record.transitions) {
    AddOnce(tr.machine, machines);
    AddOnce(tr.from, states);
    AddOnce(tr.to, states);
  }
}

std::vector<StateBar> MachineBars(const MissionRecord& record, const std::string& machine,
                                  const MissionSpan& span) {
  std::vector<const MissionTransition*> mine;
  for (const MissionTransition& tr : record.transitions) {
    if (tr.machine == machine) mine.push_back(&tr);
  }
  std::stable_sort(
      mine.begin(), mine.end(),
      [](const MissionTransition* a, const MissionTransition* b) { return a->t_s < b->t_s; });
  std::vector<StateBar> bars;
  if (mine.empty()) return bars;
  bars.push_back({mine.front()->from, span.t0_s, mine.front()->t_s, ""});
  for (std::size_t k = 0; k < mine.size(); ++k) {
    bars.push_back({mine[k]->to, mine[k]->t_s, k + 1 < mine.size() ? mine[k + 1]->t_s : span.t1_s,
                    mine[k]->cause});
  }
  return bars;
}

void DrawStateBar(cv::Mat* image, const PlotPanel& row, const StateBar& bar,
                  const PlotColor& color) {
  const int x0 = row.X(bar.t0_s), x1 = row.X(bar.t1_s);
  if (x1 <= x0) return;
  cv::rectangle(*image, cv::Point(x0, row.y0_px), cv::Point(x1, row.y0_px + row.height_px),
                ToScalar(color), cv::FILLED);
  cv::line(*image, cv::Point(x0, row.y0_px), cv::Point(x0, row.y0_px + row.height_px), kWhite);
  const int width = TextWidth(bar.state, kBarTextScale);
  if (width + 6 <= x1 - x0) {
    PutText(image, bar.state, (x0 + x1 - width) / 2, row.y0_px + row.height_px / 2 + 5,
            kBarTextScale, ToScalar(TextColorOn(color)));
  }
}

/// The m-th machine's row: time along x, no values.
PlotPanel TimelineRow(const MissionSpan& span, int m) {
  PlotPanel row;
  row.t0_s = span.t0_s;
  row.t1_s = span.t1_s;
  row.x0_px = kNameWidthPx;
  row.y0_px = kTimelineTopPx + m * (kRowHeightPx + kRowGapPx);
  row.width_px = kTimelineWidthPx - kNameWidthPx - kRightMarginPx;
  row.height_px = kRowHeightPx;
  return row;
}

/// The legend's swatches: where each state's swatch goes, wrapped to the image width.
std::vector<cv::Point> LegendLayout(const std::vector<std::string>& states, int y0_px,
                                    int* bottom_px) {
  std::vector<cv::Point> at;
  int x = kNameWidthPx, y = y0_px;
  for (const std::string& state : states) {
    const int width = 22 + TextWidth(state, kBarTextScale) + 18;
    if (x + width > kTimelineWidthPx - kRightMarginPx && x > kNameWidthPx)
      x = kNameWidthPx, y += 24;
    at.emplace_back(x, y);
    x += width;
  }
  *bottom_px = y + 24;
  return at;
}

// ---- camera ----

/// The edges of mesh_o worth drawing as seen from the camera at cMo: the silhouette (one face
/// towards the camera, the other away), the creases (faces meeting at over 10 deg) with a face
/// towards the camera, and the open edges. Vertex index pairs.
std::vector<std::pair<int, int>> OutlineEdges(const TriangleMesh& mesh_o,
                                              const Eigen::Isometry3d& cMo) {
  const double kCreaseCos = std::cos(10.0 / kRadToDeg);
  struct EdgeOfFace {
    int a, b;
    std::size_t face;
    bool operator<(const EdgeOfFace& o) const { return std::tie(a, b) < std::tie(o.a, o.b); }
  };
  std::vector<EdgeOfFace> edge_faces;
  for (std::size_t i = 0; i < mesh_o.triangles.size(); ++i) {
    const Eigen::Vector3i& tri = mesh_o.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = std::minmax(tri[k], tri[(k + 1) % 3]);
      edge_faces.push_back({a, b, i});
    }
  }
  std::sort(edge_faces.begin(), edge_faces.end());
  const Eigen::Vector3d camera_o = cMo.inverse().translation();
  auto towards_camera = [&](std::size_t i) {
    const Eigen::Vector3d& p_o = mesh_o.vertices[mesh_o.triangles[i][0]];
    return mesh_o.TriangleNormal(i).dot(camera_o - p_o) > 0.0;
  };
  std::vector<std::pair<int, int>> edges;
  for (std::size_t first = 0, last = 0; first < edge_faces.size(); first = last) {
    const EdgeOfFace& e = edge_faces[first];
    while (last < edge_faces.size() && edge_faces[last].a == e.a && edge_faces[last].b == e.b)
      ++last;
    bool draw = last - first != 2;
    if (!draw) {
      const std::size_t i = e.face, j = edge_faces[first + 1].face;
      const bool front_i = towards_camera(i), front_j = towards_camera(j);
      const bool crease = mesh_o.TriangleNormal(i).dot(mesh_o.TriangleNormal(j)) < kCreaseCos;
      draw = front_i != front_j || (crease && (front_i || front_j));
    }
    if (draw) edges.emplace_back(e.a, e.b);
  }
  return edges;
}

// ---- pose ----
constexpr const char* kMissionPositionLabel = "object in the body frame, dto";

/// The samples' object position in d, truth and estimate, with the rotation error and found.
void MissionPoseTraces(const MissionRecord& record, PoseTrace* truth, PoseTrace* estimate) {
  truth->name = "truth";
  estimate->name = "estimate";
  for (const MissionSample& s : record.samples) {
    for (PoseTrace* trace : {truth, estimate}) {
      const Eigen::Vector3d& dto_m = trace == truth ? s.dto_truth_m : s.dto_estimate_m;
      trace->stamp_s.push_back(s.t_s);
      trace->x_m.push_back(dto_m.x());
      trace->y_m.push_back(dto_m.y());
      trace->z_m.push_back(dto_m.z());
    }
    estimate->rotation_error_deg.push_back(s.rotation_error_deg);
    estimate->found.push_back(s.found ? 1 : 0);
  }
}

std::vector<ChartMarker> SwitchMarkers(const MissionRecord& record) {
  std::vector<ChartMarker> markers;
  for (std::size_t k = 0; k < record.switches.size(); ++k)
    markers.push_back({record.switches[k].t_s, fmt::format("switch {}", k + 1)});
  return markers;
}

}  // namespace

MissionSpan ComputeMissionSpan(const MissionRecord& record) {
  double t0_s = std::numeric_limits<double>::infinity(), t1_s = -t0_s;
  auto add = [&](double t_s) {
    if (!std::isfinite(t_s)) return;
    t0_s = std::min(t0_s, t_s);
    t1_s = std::max(t1_s, t_s);
  };
  for (const MissionSample& s : record.samples) add(s.t_s);
  for (const MissionTransition& tr : record.transitions) add(tr.t_s);
  for (const MissionGraspSwitch& sw : record.switches) add(sw.t_s);
  if (!std::isfinite(t0_s)) return {};
  return {t0_s, t1_s > t0_s ? t1_s : t0_s + 1.0};
}

void WriteMissionPosePlot(const MissionRecord& record, const std::string& path) {
  PoseTrace truth, estimate;
  MissionPoseTraces(record, &truth, &estimate);
  WritePosePlot(truth, {estimate}, path, kMissionPositionLabel);
}

std::vector<TimeChart> MissionPoseCharts(const MissionRecord& record) {
  if (record.samples.empty()) return {};
  PoseTrace truth, estimate;
  MissionPoseTraces(record, &truth, &estimate);
  std::vector<TimeChart> charts = PoseCharts(truth, {estimate}, kMissionPositionLabel);
  for (TimeChart& chart : charts) chart.markers = SwitchMarkers(record);
  return charts;
}

std::vector<TimeChart> MissionJointCharts(const MissionRecord& record, int arm) {
  std::vector<TimeChart> charts;
  std::vector<double> t_s;
  for (const MissionSample& s : record.samples) t_s.push_back(s.t_s);
  for (int j = 0; j < ArmDof(record, arm); ++j) {
    TimeChart chart;
    chart.title =
        fmt::format("{} {} (deg)", arm == 0 ? "left arm" : "right arm", JointName(record, arm, j));
    chart.unit = "deg";
    chart.t_s = t_s;
    chart.lines = {{"target", JointSeriesDeg(record, arm, j, true), kTargetColor, 1},
                   {"actual", JointSeriesDeg(record, arm, j, false), kActualColor, 2}};
    chart.markers = SwitchMarkers(record);
    chart.height_px = 180;
    charts.push_back(std::move(chart));
  }
  return charts;
}

std::vector<TimeChart> MissionVehicleCharts(const MissionRecord& record) {
  if (record.samples.empty()) return {};
  const char* const axes[] = {"north, x", "east, y", "down, z"};
  std::vector<TimeChart> charts;
  for (int a = 0; a < 3; ++a) {
    TimeChart chart;
    chart.title = fmt::format("vehicle position in the world frame w, {} (m)", axes[a]);
    chart.unit = "m";
    ChartLine body{"body", {}, kVehicleColor, 2};
    for (const MissionSample& s : record.samples) {
      chart.t_s.push_back(s.t_s);
      body.v.push_back(s.vehicle_w_m[a]);
    }
    chart.lines = {std::move(body)};
    chart.markers = SwitchMarkers(record);
    chart.height_px = 150;
    charts.push_back(std::move(chart));
  }
  return charts;
}

void WriteHtmlJointCharts(const MissionRecord& record, std::ostream& html) {
  html << "<div class=\"joints\">\n";
  for (int arm = 0; arm < 2; ++arm) {
    html << "<div>\n";
    for (const TimeChart& chart : MissionJointCharts(record, arm)) WriteHtmlTimeChart(chart, html);
    html << "</div>\n";
  }
  html << "</div>\n";
}

std::optional<TimelineChart> MissionTimelineChart(const MissionRecord& record) {
  if (record.transitions.empty()) return std::nullopt;
  const MissionSpan span = ComputeMissionSpan(record);
  TimelineChart chart;
  chart.title = "state machines over time";
  MachinesAndStates(record, &chart.rows, &chart.states);
  for (const std::string& state : chart.states)
    chart.state_colors.push_back(StateColor(chart.states, state));
  for (std::size_t row = 0; row < chart.rows.size(); ++row) {
    for (const StateBar& bar : MachineBars(record, chart.rows[row], span)) {
      const std::size_t state =
          std::find(chart.states.begin(), chart.states.end(), bar.state) - chart.states.begin();
      chart.bars.push_back(
          {row, state, bar.t0_s, bar.t1_s,
           bar.cause.empty() ? "the state at the start" : "entered: " + bar.cause});
    }
  }
  chart.markers = SwitchMarkers(record);
  chart.t0_s = span.t0_s;
  chart.t1_s = span.t1_s;
  return chart;
}

bool WriteMissionJointPlot(const MissionRecord& record, const std::string& path) {
  const int dof[2] = {ArmDof(record, 0), ArmDof(record, 1)};
  const int rows = std::max(dof[0], dof[1]);
  if (record.samples.empty() || rows == 0) return false;
  const MissionSpan span = ComputeMissionSpan(record);
  std::vector<double> t_s;
  for (const MissionSample& s : record.samples) t_s.push_back(s.t_s);
  cv::Mat image = WhiteCanvas(2 * kJointColumnWidthPx,
                              kJointTopPx + rows * (kJointPanelHeightPx + kJointGapPx));
  const char* const arm_names[2] = {"left arm", "right arm"};
  for (int arm = 0; arm < 2; ++arm) {
    const int column_x0 = arm * kJointColumnWidthPx;
    PutText(&image,
            fmt::format("{}: target thin orange, actual thick blue, grasp switches red",
                        arm_names[arm]),
            column_x0 + 10, 22, 0.5, kBlack);
    if (dof[arm] == 0)
      PutText(&image, "no joints recorded", column_x0 + 80, kJointTopPx + 20, 0.5, kGrey);
    for (int j = 0; j < dof[arm]; ++j) {
      const std::string name = JointName(record, arm, j);
      const std::vector<double> target_deg = JointSeriesDeg(record, arm, j, true);
      const std::vector<double> actual_deg = JointSeriesDeg(record, arm, j, false);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      ExpandRange(target_deg, &lo, &hi);
      ExpandRange(actual_deg, &lo, &hi);
      if (!std::isfinite(lo)) lo = -1.0, hi = 1.0;
      const double pad = std::max(1.0, 0.1 * (hi - lo));
      const int x0 = column_x0 + kPlotValueLabelWidthPx + 4;
      const PlotPanel panel{fmt::format("{} (deg)", name),
                            span.t0_s,
                            span.t1_s,
                            lo - pad,
                            hi + pad,
                            x0,
                            kJointTopPx + j * (kJointPanelHeightPx + kJointGapPx),
                            column_x0 + kJointColumnWidthPx - kRightMarginPx - x0,
                            kJointPanelHeightPx};
      DrawPanelAxes(&image, panel, "");
      for (std::size_t k = 0; k < record.switches.size(); ++k) {
        DrawPanelMarker(&image, panel, record.switches[k].t_s, fmt::format("switch {}", k + 1),
                        kSwitchColor);
      }
      DrawPanelSeries(&image, panel, t_s, target_deg, kTargetColor, 1);
      DrawPanelSeries(&image, panel, t_s, actual_deg, kActualColor, 2);
      if (j + 1 == dof[arm]) DrawPanelTimeLabels(&image, panel);
    }
  }
  WritePlotPng(image, path);
  return true;
}

bool WriteMissionTimelinePlot(const MissionRecord& record, const std::string& path) {
  if (record.transitions.empty()) return false;
  const MissionSpan span = ComputeMissionSpan(record);
  std::vector<std::string> machines, states;
  MachinesAndStates(record, &machines, &states);
  const int rows_bottom_px = kTimelineTopPx + int(machines.size()) * (kRowHeightPx + kRowGapPx);
  int legend_bottom_px = 0;
  const std::vector<cv::Point> legend =
      LegendLayout(states, rows_bottom_px + 24, &legend_bottom_px);
  cv::Mat image = WhiteCanvas(kTimelineWidthPx, legend_bottom_px + 10);
  PutText(&image, "state machines over time (red lines: grasp switches)", kNameWidthPx, 20, 0.5,
          kBlack);
  for (std::size_t m = 0; m < machines.size(); ++m) {
    const PlotPanel row = TimelineRow(span, int(m));
    PutText(&image, machines[m], 8, row.y0_px + row.height_px / 2 + 5, 0.5, kBlack);
    const std::vector<StateBar> bars = MachineBars(record, machines[m], span);
    if (bars.empty())
      PutText(&image, "no transitions", row.x0_px + 8, row.y0_px + row.height_px / 2 + 5, 0.42,
              kGrey);
    for (const StateBar& bar : bars) DrawStateBar(&image, row, bar, StateColor(states, bar.state));
    cv::rectangle(image, cv::Point(row.x0_px, row.y0_px),
                  cv::Point(row.x0_px + row.width_px, row.y0_px + row.height_px), kBlack);
    for (const MissionGraspSwitch& sw : record.switches)
      DrawPanelMarker(&image, row, sw.t_s, "", kSwitchColor);
    if (m + 1 == machines.size()) DrawPanelTimeLabels(&image, row);
  }
  for (std::size_t k = 0; k < states.size(); ++k) {
    const cv::Point& at = legend[k];
    cv::rectangle(image, at, at + cv::Point(14, 14), ToScalar(StateColor(states, states[k])),
                  cv::FILLED);
    cv::rectangle(image, at, at + cv::Point(14, 14), kBlack);
    PutText(&image, states[k], at.x + 20, at.y + 12, kBarTextScale, kBlack);
  }
  WritePlotPng(image, path);
  return true;
}

void WriteMissionCameraImage(const MissionSnapshot& snapshot, const TriangleMesh& mesh_o,
                             const std::string& path) {
  constexpr double kNearPlaneM = 0.01;
  cv::Mat image;
  if (snapshot.color.empty()) {
    image = cv::Mat(snapshot.K.height, snapshot.K.width, CV_8UC3, cv::Scalar(40, 40, 40));
  } else {
    const cv::Mat rgb(snapshot.color.height, snapshot.color.width, CV_8UC3,
                      const_cast<std::uint8_t*>(snapshot.color.data.data()));
    cv::cvtColor(rgb, image, cv::COLOR_RGB2BGR);
  }
  if (snapshot.has_pose) {
    const std::vector<std::pair<int, int>> edges = OutlineEdges(mesh_o, snapshot.cMo);
    std::vector<Eigen::Vector3d> p_c;
    p_c.reserve(mesh_o.vertices.size());
    for (const Eigen::Vector3d& p_o : mesh_o.vertices) p_c.push_back(snapshot.cMo * p_o);
    for (const auto& [a, b] : edges) {
      if (p_c[a].z() < kNearPlaneM || p_c[b].z() < kNearPlaneM) continue;
      const Eigen::Vector2d pa = snapshot.K.Project(p_c[a]), pb = snapshot.K.Project(p_c[b]);
      cv::line(image, cv::Point2d(pa.x(), pa.y()), cv::Point2d(pb.x(), pb.y()),
               cv::Scalar(255, 255, 0), 1, cv::LINE_AA);
    }
  }
  if (snapshot.has_box) {
    cv::rectangle(image, cv::Point(snapshot.box_x0, snapshot.box_y0),
                  cv::Point(snapshot.box_x1, snapshot.box_y1), cv::Scalar(0, 220, 0), 2);
  }
  const std::string stamp = fmt::format("t = {:.2f} s", snapshot.t_s);
  cv::rectangle(image, cv::Point(0, 0), cv::Point(TextWidth(stamp, 0.5) + 12, 26), kBlack,
                cv::FILLED);
  PutText(&image, stamp, 6, 18, 0.5, kWhite);
  WritePlotPng(image, path);
}

}  // namespace aerograsp
