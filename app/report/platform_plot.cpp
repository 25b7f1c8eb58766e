#include "app/report/platform_plot.h"

#include <array>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "core/platform.h"

namespace aerograsp {
namespace {

constexpr int kPanel = 520;            // pixels per view
constexpr double kPixelsPerM = 520.0;  // 1 m spans the panel
constexpr double kCentreZ_m = 0.20;    // body z shown at the panel's centre (FRD: +z down)

// Corners of a collision shape's bounding box in the body frame; cylinders and
// spheres by their bounding boxes (enough for a picture).
std::array<Eigen::Vector3d, 8> Corners(const CollisionShape& s, const Eigen::Isometry3d& dMseg) {
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  switch (s.type) {
    case CollisionShape::Type::kBox:
      half = 0.5 * s.size;
      break;
    case CollisionShape::Type::kCylinder:
      half = {s.size.x(), s.size.x(), 0.5 * s.size.y()};
      break;
    case CollisionShape::Type::kSphere:
      half = Eigen::Vector3d::Constant(s.size.x());
      break;
    case CollisionShape::Type::kMesh:
      half = Eigen::Vector3d::Constant(0.01);
      break;
  }
  std::array<Eigen::Vector3d, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(),
                                (i & 4 ? 1 : -1) * half.z());
    corners[i] = dMseg * s.segMs * local;
  }
  return corners;
}

struct View {
  int horizontal_axis;  // 0 = x (side view), 1 = y (front view)
  bool flip;            // front view seen from ahead: +y (right) drawn on the left
  cv::Point ToPixel(const Eigen::Vector3d& p_d) const {
    const double h = (flip ? -1.0 : 1.0) * p_d[horizontal_axis];
    return {static_cast<int>(kPanel / 2 + h * kPixelsPerM),
            static_cast<int>(kPanel / 2 + (p_d.z() - kCentreZ_m) * kPixelsPerM)};
  }
};

void DrawShape(const View& view, const std::array<Eigen::Vector3d, 8>& corners,
               const cv::Scalar& colour, bool filled, cv::Mat* image) {
  std::vector<cv::Point> points, hull;
  for (const Eigen::Vector3d& c : corners) points.push_back(view.ToPixel(c));
  cv::convexHull(points, hull);
  if (filled) cv::fillConvexPoly(*image, hull, colour, cv::LINE_AA);
  cv::polylines(*image, hull, true, filled ? cv::Scalar(40, 40, 40) : colour, 1, cv::LINE_AA);
}

void DrawArm(const Platform& platform, Side side, const Eigen::VectorXd& q, const View& view,
             cv::Mat* image) {
  const ArmModel& arm = platform.arm(side);
  std::vector<Eigen::Isometry3d> bMs;
  arm.SegmentPoses(q, &bMs);
  // OpenCV colours are BGR: left blue, right green.
  const cv::Scalar colour =
      side == Side::kLeft ? cv::Scalar(230, 140, 60) : cv::Scalar(80, 180, 80);
  for (std::size_t i = 0; i < arm.segments().size(); ++i) {
    for (const CollisionShape& s : arm.segments()[i].collision) {
      DrawShape(view, Corners(s, platform.dMb(side) * bMs[i]), colour, true, image);
    }
  }
  const Eigen::Isometry3d dMe = platform.dMb(side) * bMs.back();
  cv::circle(*image, view.ToPixel(dMe.translation()), 4, cv::Scalar(0, 0, 200), cv::FILLED,
             cv::LINE_AA);
  // Approach axis of the tool, 5 cm.
  cv::arrowedLine(*image, view.ToPixel(dMe.translation()),
                  view.ToPixel(dMe * Eigen::Vector3d(0, 0, 0.05)), cv::Scalar(0, 0, 200), 1,
                  cv::LINE_AA);
}

void DrawCamera(const Platform& platform, const View& view, cv::Mat* image) {
  const CameraIntrinsics& K = platform.camera();
  const double range_m = 0.6;
  const Eigen::Vector3d origin = platform.dMc().translation();
  std::vector<Eigen::Vector3d> rays = {K.Unproject(0, 0, range_m), K.Unproject(K.width, 0, range_m),
                                       K.Unproject(0, K.height, range_m),
                                       K.Unproject(K.width, K.height, range_m)};
  for (const Eigen::Vector3d& r_c : rays) {
    cv::line(*image, view.ToPixel(origin), view.ToPixel(platform.dMc() * r_c),
             cv::Scalar(160, 120, 200), 1, cv::LINE_AA);
  }
  cv::circle(*image, view.ToPixel(origin), 5, cv::Scalar(160, 60, 160), cv::FILLED, cv::LINE_AA);
}

void DrawPanel(const Platform& platform, const Eigen::VectorXd& q_left,
               const Eigen::VectorXd& q_right, const View& view, const std::string& title,
               cv::Mat* image) {
  // A 10 cm grid.
  for (int k = -5; k <= 5; ++k) {
    const int p = kPanel / 2 + static_cast<int>(k * 0.1 * kPixelsPerM);
    cv::line(*image, {p, 0}, {p, kPanel}, cv::Scalar(235, 235, 235));
    cv::line(*image, {0, p}, {kPanel, p}, cv::Scalar(235, 235, 235));
  }
  for (const CollisionShape& s : platform.safe_volume_d()) {
    DrawShape(view, Corners(s, Eigen::Isometry3d::Identity()), cv::Scalar(0, 0, 220), false, image);
  }
  for (const StaticFrameTree::Link& link : platform.vehicle().links()) {
    if (link.name == platform.config().safe_volume_link) continue;
    for (const CollisionShape& s : link.collision) {
      DrawShape(view, Corners(s, link.rootMlink), cv::Scalar(150, 150, 150), true, image);
    }
  }
  DrawCamera(platform, view, image);
  DrawArm(platform, Side::kLeft, q_left, view, image);
  DrawArm(platform, Side::kRight, q_right, view, image);
  cv::putText(*image, title, {10, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(20, 20, 20), 1,
              cv::LINE_AA);
}

}  // namespace

void WritePlatformPlot(const Platform& platform, const Eigen::VectorXd& q_left,
                       const Eigen::VectorXd& q_right, const std::string& png_path) {
  cv::Mat image(kPanel + 30, 2 * kPanel, CV_8UC3, cv::Scalar(255, 255, 255));
  // Each view draws into its own region of the image, which clips it.
  cv::Mat side = image(cv::Rect(0, 0, kPanel, kPanel));
  cv::Mat front = image(cv::Rect(kPanel, 0, kPanel, kPanel));
  DrawPanel(platform, q_left, q_right, View{0, false},
            "side view (x forward ->, z down), grid 10 cm", &side);
  DrawPanel(platform, q_left, q_right, View{1, true},
            "front view (seen from ahead: left arm on the right)", &front);
  cv::line(image, {kPanel, 0}, {kPanel, kPanel}, cv::Scalar(120, 120, 120));
  cv::putText(image,
              "red box: safe volume   purple: camera field of view (0.6 m)   blue: left arm   "
              "green: right arm   red dot: tool point, arrow: approach axis",
              {10, kPanel + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(20, 20, 20), 1,
              cv::LINE_AA);
  bool ok = false;
  try {
    ok = cv::imwrite(png_path, image);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(png_path + ": cannot write image: " + e.what());
  }
  if (!ok) throw std::runtime_error(png_path + ": cannot write image");
}

}  // namespace aerograsp
