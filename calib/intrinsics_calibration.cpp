#include "calib/intrinsics_calibration.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace aerograsp {

IntrinsicsResult CalibrateIntrinsics(const std::vector<IntrinsicsView>& views, int width,
                                     int height, int min_views) {
  IntrinsicsResult result;
  result.K.width = width;
  result.K.height = height;
  if (static_cast<int>(views.size()) < min_views) {
    result.message = "only " + std::to_string(views.size()) + " views (at least " +
                     std::to_string(min_views) + " needed)";
    return result;
  }
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (views[v].corners.size() < 4) {
      result.message = "view " + std::to_string(v) + " has " +
                       std::to_string(views[v].corners.size()) + " corners (at least 4 needed)";
      return result;
    }
    std::vector<cv::Point3f> p_t;
    std::vector<cv::Point2f> px;
    for (const auto& [point_t, pixel] : views[v].corners) {
      if (std::abs(point_t.z()) > 1e-9) {
        result.message =
            "the board is not planar (a corner at z_t = " + std::to_string(point_t.z()) + " m)";
        return result;
      }
      p_t.emplace_back(static_cast<float>(point_t.x()), static_cast<float>(point_t.y()), 0.0f);
      px.emplace_back(static_cast<float>(pixel.x()), static_cast<float>(pixel.y()));
    }
    object_points.push_back(std::move(p_t));
    image_points.push_back(std::move(px));
  }
  cv::Mat camera_matrix, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat std_intrinsics, std_extrinsics, per_view_errors;
  try {
    result.rms_px = cv::calibrateCamera(
        object_points, image_points, cv::Size(width, height), camera_matrix, distortion, rvecs,
        tvecs, std_intrinsics, std_extrinsics, per_view_errors, cv::CALIB_FIX_K3,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  } catch (const cv::Exception& e) {
    result.message = std::string("OpenCV's calibrateCamera failed: ") + e.what();
    return result;
  }
  result.K.fx = camera_matrix.at<double>(0, 0);
  result.K.fy = camera_matrix.at<double>(1, 1);
  result.K.cx = camera_matrix.at<double>(0, 2);
  result.K.cy = camera_matrix.at<double>(1, 2);
  for (int i = 0; i < 5 && i < static_cast<int>(distortion.total()); ++i)
    result.distortion[i] = distortion.at<double>(i);
  for (int v = 0; v < per_view_errors.rows; ++v)
    result.per_view_rms_px.push_back(per_view_errors.at<double>(v));
  if (!std::isfinite(result.rms_px) || !(result.K.fx > 0.0) || !(result.K.fy > 0.0)) {
    result.message = "the solve diverged (are the views all at the same tilt?)";
    return result;
  }
  result.ok = true;
  return result;
}

}  // namespace aerograsp
