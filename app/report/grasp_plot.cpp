#include "app/report/grasp_plot.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace aerograsp {
namespace {

constexpr int kSize = 640;  // pixels

/// Oblique orthographic view of the body frame d: from ahead of the vehicle,
/// 35 deg to its left and 30 deg above.
struct View {
  Eigen::Vector3d right, up, into;  // unit axes in d; `into` points away from the viewer
  Eigen::Vector3d centre_d;
  double pixels_per_m = 1.0;

  View(const Eigen::Vector3d& centre, double radius_m) : centre_d(centre) {
    const double az = 35.0 * M_PI / 180.0, el = 30.0 * M_PI / 180.0;
    // Viewer at +x (ahead), -y (left), -z (above): looking back, right and down.
    into = Eigen::Vector3d(-std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const Eigen::Vector3d up_d(0, 0, -1);
    right = into.cross(up_d).normalized();
    up = right.cross(into).normalized();
    pixels_per_m = 0.42 * kSize / radius_m;
  }
  cv::Point2f ToPixel(const Eigen::Vector3d& p_d) const {
    const Eigen::Vector3d r = p_d - centre_d;
    return {static_cast<float>(kSize / 2 + r.dot(right) * pixels_per_m),
            static_cast<float>(kSize / 2 - r.dot(up) * pixels_per_m)};
  }
  cv::Point ToInt(const Eigen::Vector3d& p_d) const {
    const cv::Point2f f = ToPixel(p_d);
    return {static_cast<int>(std::lround(f.x)), static_cast<int>(std::lround(f.y))};
  }
};

void DrawMesh(const TriangleMesh& mesh, const Eigen::Isometry3d& dMo, const View& view,
              cv::Mat* image) {
  std::vector<Eigen::Vector3d> v_d(mesh.vertices.size());
  for (std::size_t i = 0; i < v_d.size(); ++i) v_d[i] = dMo * mesh.vertices[i];
  std::vector<double> depth(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    depth[i] = (v_d[t[0]] + v_d[t[1]] + v_d[t[2]]).dot(view.into);
  }
  std::vector<std::size_t> order(mesh.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return depth[a] > depth[b]; });
  for (std::size_t i : order) {
    const Eigen::Vector3d n_d = dMo.linear() * mesh.TriangleNormal(i);
    const double facing = -n_d.dot(view.into);
    if (facing <= 0.0) continue;  // back face of a closed mesh
    const Eigen::Vector3i& t = mesh.triangles[i];
    Eigen::Vector3d rgb(170, 170, 175);
    if (!mesh.colors.empty()) {
      rgb.setZero();
      for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) rgb[c] += mesh.colors[t[k]][c] / 3.0;
      }
    }
    const double shade = 0.35 + 0.65 * facing;
    const cv::Point pts[3] = {view.ToInt(v_d[t[0]]), view.ToInt(v_d[t[1]]), view.ToInt(v_d[t[2]])};
    cv::fillConvexPoly(*image, pts, 3, cv::Scalar(rgb[2] * shade, rgb[1] * shade, rgb[0] * shade),
                       cv::LINE_AA);
  }
}

}  // namespace

void WriteGraspPlot(const GraspObject& object, const ContactSet& contacts,
                    const std::vector<DualGrasp>& ranked, int count, const Eigen::Isometry3d& dMo,
                    const std::string& png_path) {
  double radius = 0.0;
  for (const Eigen::Vector3d& v : object.mesh_o.vertices) {
    radius = std::max(radius, (v - object.com_o).norm());
  }
  const View view(dMo * object.com_o, radius + 0.09);
  cv::Mat image(kSize, kSize, CV_8UC3, cv::Scalar(255, 255, 255));
  DrawMesh(object.mesh_o, dMo, view, &image);

  const int shown = std::min<int>(count, static_cast<int>(ranked.size()));
  for (int k = shown - 1; k >= 0; --k) {  // best drawn last, on top
    const DualGrasp& d = ranked[k];
    const int thickness = k == 0 ? 3 : 1;
    for (const ArmGrasp* g : {&d.left, &d.right}) {
      // BGR: left blue, right red.
      const cv::Scalar colour =
          g->side == Side::kLeft ? cv::Scalar(200, 90, 20) : cv::Scalar(30, 30, 210);
      const ContactPair& p = contacts.pairs[g->pair];
      const Eigen::Vector3d a_d = dMo * p.a.p_o, b_d = dMo * p.b.p_o, c_d = dMo * p.center_o();
      cv::line(image, view.ToInt(a_d), view.ToInt(b_d), colour, thickness, cv::LINE_AA);
      cv::circle(image, view.ToInt(a_d), 3 + thickness, colour, cv::FILLED, cv::LINE_AA);
      cv::circle(image, view.ToInt(b_d), 3 + thickness, colour, cv::FILLED, cv::LINE_AA);
      const Eigen::Vector3d z_d = g->dMg.linear().col(2);
      cv::arrowedLine(image, view.ToInt(c_d - 0.08 * z_d), view.ToInt(c_d), colour, thickness,
                      cv::LINE_AA, 0, 0.2);
      cv::putText(image, std::to_string(k + 1), view.ToInt(c_d - 0.09 * z_d),
                  cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv::LINE_AA);
    }
  }
  cv::putText(image, object.name + ": best " + std::to_string(shown) + " dual grasps", {10, 22},
              cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, "left arm blue, right arm red; arrows: approach; 1 = best", {10, kSize - 12},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  if (!cv::imwrite(png_path, image)) {
    throw std::runtime_error(png_path + ": cannot write the PNG");
  }
}

}  // namespace aerograsp
