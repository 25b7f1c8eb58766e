#include "app/pose_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace aerograsp {
namespace {

constexpr int kWidth = 1200, kPanelHeight = 190, kLeft = 80, kRight = 20, kTop = 30, kGap = 40;

const cv::Scalar kColors[] = {cv::Scalar(200, 60, 30), cv::Scalar(30, 140, 230), cv::Scalar(60, 170, 60)};

struct Panel {
  std::string title;
  double t0, t1, lo, hi;
  int y0;
  cv::Point At(double t, double v) const {
    const double fx = (t - t0) / std::max(1e-9, t1 - t0), fy = (v - lo) / std::max(1e-12, hi - lo);
    return {kLeft + int(fx * (kWidth - kLeft - kRight)), y0 + kPanelHeight - int(fy * kPanelHeight)};
  }
};

void DrawAxes(cv::Mat* img, const Panel& p, const std::string& unit) {
  cv::rectangle(*img, cv::Point(kLeft, p.y0), cv::Point(kWidth - kRight, p.y0 + kPanelHeight), cv::Scalar(0, 0, 0));
  cv::putText(*img, p.title, cv::Point(kLeft, p.y0 - 8), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  for (int k = 0; k <= 4; ++k) {
    const double v = p.lo + (p.hi - p.lo) * k / 4.0;
    const cv::Point a = p.At(p.t0, v);
    cv::line(*img, a, cv::Point(kWidth - kRight, a.y), cv::Scalar(225, 225, 225));
    cv::putText(*img, fmt::format("{:.3f}{}", v, unit), cv::Point(4, a.y + 4), cv::FONT_HERSHEY_SIMPLEX, 0.35,
                cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  }
}

void DrawSeries(cv::Mat* img, const Panel& p, const std::vector<double>& t, const std::vector<double>& v,
                const cv::Scalar& color, int thickness) {
  bool has_prev = false;
  cv::Point prev;
  for (std::size_t i = 0; i < t.size() && i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      has_prev = false;
      continue;
    }
    const cv::Point q = p.At(t[i], std::clamp(v[i], p.lo, p.hi));
    if (has_prev) cv::line(*img, prev, q, color, thickness, cv::LINE_AA);
    prev = q;
    has_prev = true;
  }
}

void Range(const std::vector<double>& v, double* lo, double* hi) {
  for (double x : v) {
    if (std::isfinite(x)) {
      *lo = std::min(*lo, x);
      *hi = std::max(*hi, x);
    }
  }
}

}  // namespace

void WritePosePlot(const PoseTrace& truth, const std::vector<PoseTrace>& estimates, const std::string& path) {
  const int panels = 5;
  cv::Mat img(kTop + panels * (kPanelHeight + kGap) + 20, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const double t0 = truth.stamp_s.empty() ? 0.0 : truth.stamp_s.front();
  const double t1 = truth.stamp_s.empty() ? 1.0 : truth.stamp_s.back();
  const char* axes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    auto pick = [a](const PoseTrace& tr) -> const std::vector<double>& {
      return a == 0 ? tr.x_m : a == 1 ? tr.y_m : tr.z_m;
    };
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    Range(pick(truth), &lo, &hi);
    for (const PoseTrace& e : estimates) Range(pick(e), &lo, &hi);
    if (!std::isfinite(lo)) lo = 0.0, hi = 1.0;
    const double pad = std::max(0.005, 0.1 * (hi - lo));
    const Panel p{fmt::format("cMo position {} (m): truth black, {}", axes[a], [&] {
                    std::string s;
                    for (std::size_t k = 0; k < estimates.size(); ++k) s += (k ? ", " : "") + estimates[k].name;
                    return s;
                  }()),
                  t0, t1, lo - pad, hi + pad, kTop + a * (kPanelHeight + kGap)};
    DrawAxes(&img, p, "");
    DrawSeries(&img, p, truth.stamp_s, pick(truth), cv::Scalar(0, 0, 0), 2);
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      DrawSeries(&img, p, estimates[k].stamp_s, pick(estimates[k]), kColors[k % 3], 1);
    }
  }
  {
    double lo = 0.0, hi = 1.0;
    for (const PoseTrace& e : estimates) Range(e.rotation_error_deg, &lo, &hi);
    hi = std::min(hi, 30.0);
    const Panel p{"rotation error (deg, over the object's symmetries)", t0, t1, 0.0, hi * 1.1,
                  kTop + 3 * (kPanelHeight + kGap)};
    DrawAxes(&img, p, "");
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      DrawSeries(&img, p, estimates[k].stamp_s, estimates[k].rotation_error_deg, kColors[k % 3], 1);
    }
  }
  {
    const Panel p{"found (1) / lost (0)", t0, t1, -0.2, 1.2 + 0.1 * estimates.size(), kTop + 4 * (kPanelHeight + kGap)};
    DrawAxes(&img, p, "");
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      std::vector<double> v(estimates[k].found.begin(), estimates[k].found.end());
      for (double& x : v) x += 0.05 * k;
      DrawSeries(&img, p, estimates[k].stamp_s, v, kColors[k % 3], 2);
    }
  }
  if (!cv::imwrite(path, img)) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace aerograsp
