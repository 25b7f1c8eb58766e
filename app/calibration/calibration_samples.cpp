#include "app/calibration/calibration_samples.h"

#include <yaml-cpp/yaml.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace aerograsp {

void EmitTagBoard(const TagBoardConfig& board, YAML::Emitter* y) {
  *y << YAML::BeginMap;
  *y << YAML::Key << "family" << YAML::Value << board.family << YAML::Key << "rows" << YAML::Value
     << board.rows << YAML::Key << "cols" << YAML::Value << board.cols << YAML::Key << "tag_size_m"
     << YAML::Value << board.tag_size_m << YAML::Key << "spacing_m" << YAML::Value
     << board.spacing_m << YAML::Key << "margin_m" << YAML::Value << board.margin_m << YAML::Key
     << "first_id" << YAML::Value << board.first_id;
  *y << YAML::EndMap;
}

void EmitCorners(const std::vector<BoardCorner>& corners, YAML::Emitter* y) {
  *y << YAML::BeginSeq;
  for (const auto& [p_t, px] : corners)
    *y << YAML::Flow << std::vector<double>{p_t.x(), p_t.y(), p_t.z(), px.x(), px.y()};
  *y << YAML::EndSeq;
}

std::vector<BoardCorner> ReadCorners(const YAML::Node& list, const ConfigNode& file,
                                     const std::string& where) {
  std::vector<BoardCorner> corners;
  if (!list || !list.IsSequence()) file.Fail(where, "expected a list of corners [x, y, z, u, v]");
  for (const YAML::Node& row : list) {
    const auto v = row.as<std::vector<double>>();
    if (v.size() != 5) file.Fail(where, "each corner is x, y, z, u, v");
    CheckFinite(file.source(), where + "[" + std::to_string(corners.size()) + "]", v);
    corners.emplace_back(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector2d(v[3], v[4]));
  }
  return corners;
}

void WriteColorPng(const ColorImage& rgb, const std::string& path) {
  const cv::Mat view(rgb.height, rgb.width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data.data()));
  cv::Mat bgr;
  cv::cvtColor(view, bgr, cv::COLOR_RGB2BGR);
  if (!cv::imwrite(path, bgr)) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace aerograsp
