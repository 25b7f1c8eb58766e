#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "app/report/mission_report.h"
#include "core/shape_mesh.h"
#include "tests/app/headless_browser.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr std::uint8_t kFrameRgb[3] = {90, 120, 150};

/// 10 s of a two-arm mission: 200 samples, six transitions, two grasp switches and a
/// snapshot of a plain frame with a 0.2 m box 1 m in front of the camera.
MissionRecord SyntheticRecord() {
  MissionRecord record;
  record.object_name = "crawler";
  for (int arm = 0; arm < 2; ++arm) {
    for (int j = 0; j < 4; ++j)
      record.joint_names[arm].push_back((arm ? "right_j" : "left_j") + std::to_string(j + 1));
  }
  for (int i = 0; i < 200; ++i) {
    MissionSample s;
    s.t_s = 0.05 * i;
    s.found = s.t_s > 2.0;
    s.estimate_valid = s.found;
    s.dto_truth_m = Eigen::Vector3d(0.5 + 0.01 * std::sin(s.t_s), 0.02, 0.3);
    if (s.found) {
      s.dto_estimate_m = s.dto_truth_m + Eigen::Vector3d(0.003, -0.002, 0.001);
      s.rotation_error_deg = 1.5;
    }
    for (int arm = 0; arm < 2; ++arm) {
      s.q_target_rad[arm] = Eigen::VectorXd(4);
      s.q_actual_rad[arm] = Eigen::VectorXd(4);
      for (int j = 0; j < 4; ++j) {
        s.q_target_rad[arm][j] = 0.5 * std::sin(0.4 * s.t_s + j + arm);
        s.q_actual_rad[arm][j] = 0.5 * std::sin(0.4 * (s.t_s - 0.2) + j + arm);
      }
    }
    record.samples.push_back(s);
  }
  record.transitions = {{0.5, "global", "idle", "takeoff", "armed and ready"},
                        {1.0, "vehicle", "climbing", "hover", "altitude reached"},
                        {2.1, "vision", "searching", "found", "detector box in 3 frames"},
                        {3.0, "planner", "idle", "planned", "12 feasible dual grasps"},
                        {4.0, "arms", "home", "servoing", "grasp ready"},
                        {9.0, "global", "takeoff", "grasped", "both grippers holding"}};
  record.switches = {{6.0, 3, 4, "left grasp out of reach"}, {8.0, 5, 4, "right grasp collides"}};
  MissionSnapshot snapshot;
  snapshot.t_s = 5.0;
  snapshot.color = ColorImage(snapshot.K.width, snapshot.K.height);
  for (std::size_t k = 0; k < snapshot.color.data.size(); ++k)
    snapshot.color.data[k] = kFrameRgb[k % 3];
  snapshot.has_box = true;
  snapshot.box_x0 = 200, snapshot.box_y0 = 150, snapshot.box_x1 = 440, snapshot.box_y1 = 330;
  snapshot.has_pose = true;
  snapshot.cMo.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  record.snapshot = snapshot;
  return record;
}

class MissionReportTest : public ::testing::Test {
 protected:
  // A folder per process and test: ctest runs tests in parallel processes.
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("aerograsp_mission_report_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    out_dir_ = (dir_ / "report").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  void Write(const MissionRecord& record, const ReportRow& headline = {},
             const std::vector<ReportRow>& runs = {}) {
    WriteMissionReport(record, mesh_o_, headline, runs, out_dir_);
  }
  std::string ReadHtml() const {
    std::ifstream file(fs::path(out_dir_) / "index.html");
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
  }

  fs::path dir_;
  std::string out_dir_;
  const TriangleMesh mesh_o_ = MakeBoxMesh(Eigen::Vector3d(0.2, 0.2, 0.2));
};

TEST_F(MissionReportTest, HtmlReferencesEveryImageAndListsTransitionsSwitchesAndRuns) {
  const MissionRecord record = SyntheticRecord();
  Write(record, {{"success", "yes"}, {"time to grasp", "9.0 s"}},
        {{{"seed", "1"}, {"success", "yes"}}, {{"seed", "2"}, {"success", "no"}}});
  ASSERT_TRUE(fs::exists(fs::path(out_dir_) / "index.html"));
  const std::string html = ReadHtml();
  EXPECT_THAT(html, HasSubstr("<title>Mission report: crawler</title>"));
  for (const char* image : {"pose.png", "joints.png", "timeline.png", "camera.png"}) {
    EXPECT_THAT(html, HasSubstr(std::string("src=\"") + image + "\"")) << image;
  }
  for (const MissionTransition& tr : record.transitions)
    EXPECT_THAT(html, HasSubstr(tr.cause)) << tr.cause;
  EXPECT_THAT(html, HasSubstr("searching -&gt; found"));
  for (const MissionGraspSwitch& sw : record.switches)
    EXPECT_THAT(html, HasSubstr(sw.reason)) << sw.reason;
  EXPECT_THAT(html, HasSubstr("<td>time to grasp</td><td>9.0 s</td>"));
  EXPECT_THAT(html, HasSubstr("<th>seed</th><th>success</th>"));
  EXPECT_THAT(html, HasSubstr("<td>2</td><td>no</td>"));
  // No network needed: nothing is loaded from elsewhere (Chart.js is inlined).
  EXPECT_THAT(html, Not(HasSubstr("src=\"http")));
  EXPECT_THAT(html, Not(HasSubstr("href=\"http")));
  EXPECT_THAT(html, Not(HasSubstr("<script src")));
}

TEST_F(MissionReportTest, HtmlHoldsAChartPerPanelWithItsDataAndLinksThePngs) {
  Write(SyntheticRecord());
  const std::string html = ReadHtml();
  // Pose: x, y, z, rotation error, found; joints: 4 per arm; the vehicle: x, y, z; the timeline.
  EXPECT_EQ(CountCharts(html), 5 + 8 + 3 + 1);
  for (const char* image : {"pose.png", "joints.png", "timeline.png"})
    EXPECT_THAT(html, HasSubstr(std::string("<a href=\"") + image + "\">PNG</a>")) << image;
  EXPECT_THAT(html, HasSubstr("\"title\":\"right arm right_j4 (deg)\""));
  EXPECT_THAT(html, HasSubstr("{\"t\":6,\"label\":\"switch 1\"}"));
  EXPECT_THAT(html, HasSubstr("entered: detector box in 3 frames"));
  EXPECT_THAT(html, HasSubstr("Chart.js v3.9.1"));
}

TEST_F(MissionReportTest, EveryPlotLoadsWithAPlausibleSize) {
  Write(SyntheticRecord());
  for (const char* image : {"pose.png", "joints.png", "timeline.png"}) {
    const cv::Mat plot = cv::imread((fs::path(out_dir_) / image).string());
    ASSERT_FALSE(plot.empty()) << image;
    EXPECT_GE(plot.cols, 800) << image;
    EXPECT_GE(plot.rows, 250) << image;
    EXPECT_LE(plot.cols * plot.rows, 4000 * 4000) << image;
  }
  const cv::Mat camera = cv::imread((fs::path(out_dir_) / "camera.png").string());
  ASSERT_FALSE(camera.empty());
  EXPECT_EQ(camera.cols, 640);
  EXPECT_EQ(camera.rows, 480);
}

/// Whether some pixel within `radius` of (u, v) differs from the plain frame.
bool DiffersFromFrameNear(const cv::Mat& bgr, int u, int v, int radius) {
  for (int y = v - radius; y <= v + radius; ++y) {
    for (int x = u - radius; x <= u + radius; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      if (p[0] != kFrameRgb[2] || p[1] != kFrameRgb[1] || p[2] != kFrameRgb[0]) return true;
    }
  }
  return false;
}

TEST_F(MissionReportTest, CameraImageOverlaysTheModelAtTheEstimatedPoseAndTheBox) {
  const MissionRecord record = SyntheticRecord();
  Write(record);
  const cv::Mat camera = cv::imread((fs::path(out_dir_) / "camera.png").string());
  ASSERT_FALSE(camera.empty());
  const MissionSnapshot& snap = *record.snapshot;
  // The middle of the box's near right edge (x = 0.1 m, y = 0, z = -0.1 m in o).
  const Eigen::Vector2d edge_px = snap.K.Project(snap.cMo * Eigen::Vector3d(0.1, 0.0, -0.1));
  EXPECT_TRUE(DiffersFromFrameNear(camera, int(std::lround(edge_px.x())),
                                   int(std::lround(edge_px.y())), 2));
  // The detector box's left side, well away from the model.
  EXPECT_TRUE(DiffersFromFrameNear(camera, snap.box_x0, (snap.box_y0 + snap.box_y1) / 2, 1));
  // Far from the model, the box and the time stamp the frame is untouched.
  EXPECT_FALSE(DiffersFromFrameNear(camera, 600, 440, 10));
  // The near face is not cut into triangles, and the far face's edges are hidden behind it.
  EXPECT_FALSE(DiffersFromFrameNear(camera, 320, 240, 3));
  const Eigen::Vector2d hidden_px = snap.K.Project(snap.cMo * Eigen::Vector3d(0.1, 0.0, 0.1));
  EXPECT_FALSE(DiffersFromFrameNear(camera, int(std::lround(hidden_px.x())),
                                    int(std::lround(hidden_px.y())), 3));
}

TEST_F(MissionReportTest, AModelBehindTheCameraIsNotDrawn) {
  MissionRecord record = SyntheticRecord();
  record.snapshot->has_box = false;
  record.snapshot->cMo.translation() = Eigen::Vector3d(0.0, 0.0, -1.0);
  Write(record);
  const cv::Mat camera = cv::imread((fs::path(out_dir_) / "camera.png").string());
  ASSERT_FALSE(camera.empty());
  EXPECT_FALSE(DiffersFromFrameNear(camera, 320, 240, 150));
}

TEST_F(MissionReportTest, AnUnwritableFolderThrowsNamingIt) {
  const fs::path file = dir_ / "plain_file";
  std::ofstream(file) << "not a folder";
  out_dir_ = (file / "report").string();
  try {
    Write(SyntheticRecord());
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr(out_dir_));
  }
}

TEST_F(MissionReportTest, AnEmptyRecordStillWritesTheHtml) {
  MissionRecord record;
  record.object_name = "pipe";
  Write(record, {{"success", "no"}});
  const std::string html = ReadHtml();
  for (const char* text :
       {"Mission report: pipe", "<td>success</td><td>no</td>", "No samples were recorded.",
        "No joint samples were recorded.", "No state transitions were recorded.",
        "No camera snapshot was recorded."}) {
    EXPECT_THAT(html, HasSubstr(text)) << text;
  }
  EXPECT_THAT(html, Not(HasSubstr("<img")));
  for (const char* image : {"pose.png", "joints.png", "timeline.png", "camera.png"}) {
    EXPECT_FALSE(fs::exists(fs::path(out_dir_) / image)) << image;
  }
}

TEST_F(MissionReportTest, TextIsHtmlEscaped) {
  MissionRecord record;
  record.object_name = "pipe <2\" & 'co'>";
  record.transitions = {{1.0, "vision", "lost", "found", "score > 0.8 & <b>stable</b>"}};
  Write(record, {{"<script>", "a & b"}});
  const std::string html = ReadHtml();
  EXPECT_THAT(html, HasSubstr("pipe &lt;2&quot; &amp; &#39;co&#39;&gt;"));
  EXPECT_THAT(html, HasSubstr("score &gt; 0.8 &amp; &lt;b&gt;stable&lt;/b&gt;"));
  EXPECT_THAT(html, HasSubstr("<td>&lt;script&gt;</td><td>a &amp; b</td>"));
  EXPECT_THAT(html, Not(HasSubstr("<td><script>")));
  EXPECT_THAT(html, Not(HasSubstr("<b>")));  // nor in the charts' JSON
  EXPECT_THAT(html, HasSubstr("\\u003cb>stable\\u003c/b>"));
}

/// The report of SyntheticRecord() opened in headless Chromium (Debian's `chromium`; the tests
/// skip where it is not installed). The screenshots stay in the build folder.
class MissionReportInBrowserTest : public MissionReportTest {
 protected:
  void SetUp() override {
    MissionReportTest::SetUp();
    chromium_ = FindChromium();
    if (chromium_.empty())
      GTEST_SKIP()
          << "chromium is not installed (Debian package chromium, scripts/install_deps.sh)";
  }
  BrowserPage Load(const std::string& html_path, const std::string& screenshot_name) const {
    return LoadInChromium(chromium_, html_path, ScreenshotPath(screenshot_name),
                          (dir_ / "chromium_profile").string());
  }

  std::string chromium_;
};

TEST_F(MissionReportInBrowserTest, EveryChartIsDrawnWithoutAConsoleMessage) {
  Write(SyntheticRecord());
  const std::string screenshot = ScreenshotPath("mission_report.png");
  fs::remove(screenshot);
  const BrowserPage page = Load((fs::path(out_dir_) / "index.html").string(), "mission_report.png");
  EXPECT_THAT(page.console, ::testing::IsEmpty());
  EXPECT_EQ(BodyAttribute(page.dom, "data-charts-error"), "");
  EXPECT_EQ(BodyAttribute(page.dom, "data-charts-drawn"), std::to_string(CountCharts(ReadHtml())));
  EXPECT_THAT(page.dom, HasSubstr("Showing the whole record, 0.00 to 9.95 s."));
  const cv::Mat shot = cv::imread(screenshot);
  ASSERT_FALSE(shot.empty()) << screenshot;
  EXPECT_EQ(shot.cols, 1400);
}

TEST_F(MissionReportInBrowserTest, DraggingAcrossAChartZoomsEveryChartToThatSpan) {
  Write(SyntheticRecord());
  // The page with a script that drags across the first chart's middle half (2.49 s to 7.46 s
  // of the record's 0 to 9.95 s) and writes every chart's time axis into <body>.
  std::string html = ReadHtml();
  const std::string drag = R"(<script>
(function () {
  const chart = Object.values(Chart.instances)[0];
  const box = chart.canvas.getBoundingClientRect();
  const area = chart.chartArea;
  const at = (f) => box.left + area.left + f * (area.right - area.left);
  const y = box.top + (area.top + area.bottom) / 2;
  const mouse = (type, target, f) => target.dispatchEvent(
      new MouseEvent(type, {clientX: at(f), clientY: y, button: 0, bubbles: true}));
  mouse('mousedown', chart.canvas, 0.25);
  mouse('mousemove', window, 0.5);
  mouse('mouseup', window, 0.75);
  const ranges = Object.values(Chart.instances).map(
      (c) => c.scales.x.min.toFixed(2) + '..' + c.scales.x.max.toFixed(2));
  document.body.setAttribute('data-test-ranges', Array.from(new Set(ranges)).join(' '));
  document.body.setAttribute('data-test-charts', String(ranges.length));
})();
</script>
)";
  html.insert(html.rfind("</body>"), drag);
  const std::string dragged = (dir_ / "dragged.html").string();
  std::ofstream(dragged) << html;
  const BrowserPage page = Load(dragged, "mission_report_zoomed.png");
  EXPECT_THAT(page.console, ::testing::IsEmpty());
  EXPECT_EQ(BodyAttribute(page.dom, "data-test-charts"), std::to_string(CountCharts(html)));
  // One range for all (pointer positions are whole pixels: 0.01 s here).
  const std::string ranges = BodyAttribute(page.dom, "data-test-ranges");
  ASSERT_THAT(ranges, Not(HasSubstr(" ")));
  double t0_s = NAN, t1_s = NAN;
  ASSERT_EQ(std::sscanf(ranges.c_str(), "%lf..%lf", &t0_s, &t1_s), 2) << ranges;
  EXPECT_NEAR(t0_s, 0.25 * 9.95, 0.02);
  EXPECT_NEAR(t1_s, 0.75 * 9.95, 0.02);
  EXPECT_THAT(page.dom, HasSubstr(" s of 0.00 to 9.95 s."));
}

}  // namespace
}  // namespace aerograsp
