#include "detection/box_detector.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace aerograsp {

std::vector<Detection> DecodeCenterNet(const CenterNetMaps& maps, int image_width, int image_height,
                                       float min_score, int max_detections) {
  std::vector<Detection> out;
  const std::size_t n = std::size_t(std::max(0, maps.width)) * std::max(0, maps.height);
  if (n == 0 || maps.heat_logit.size() != n || maps.offset_x.size() != n ||
      maps.offset_y.size() != n || maps.log_width.size() != n || maps.log_height.size() != n ||
      image_width <= 0 || image_height <= 0) {
    return out;
  }
  const double cell_x = double(image_width) / maps.width,
               cell_y = double(image_height) / maps.height;
  const float min_logit = std::log(min_score / std::max(1e-6f, 1.0f - min_score));
  for (int y = 0; y < maps.height; ++y) {
    for (int x = 0; x < maps.width; ++x) {
      const float v = maps.heat_logit[std::size_t(y) * maps.width + x];
      if (!std::isfinite(v) || v < min_logit) continue;
      bool peak = true;
      for (int dy = -1; dy <= 1 && peak; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= maps.width || yy >= maps.height)
            continue;
          const float w = maps.heat_logit[std::size_t(yy) * maps.width + xx];
          // Ties go to the first in raster order.
          if (w > v || (w == v && (yy < y || (yy == y && xx < x)))) {
            peak = false;
            break;
          }
        }
      }
      if (!peak) continue;
      const std::size_t i = std::size_t(y) * maps.width + x;
      const float ox = maps.offset_x[i], oy = maps.offset_y[i], lw = maps.log_width[i],
                  lh = maps.log_height[i];
      if (!std::isfinite(ox) || !std::isfinite(oy) || !std::isfinite(lw) || !std::isfinite(lh))
        continue;
      const double cx = (x + std::clamp(ox, 0.0f, 1.0f)) * cell_x,
                   cy = (y + std::clamp(oy, 0.0f, 1.0f)) * cell_y;
      const double w = std::exp(std::clamp(lw, -3.0f, 4.0f)) * cell_x,
                   h = std::exp(std::clamp(lh, -3.0f, 4.0f)) * cell_y;
      Detection d;
      d.score = 1.0f / (1.0f + std::exp(-v));
      d.box = PixelBox{int(std::lround(cx - w / 2)), int(std::lround(cy - h / 2)),
                       int(std::lround(cx + w / 2)), int(std::lround(cy + h / 2))}
                  .Clipped(image_width, image_height);
      if (!d.box.empty()) out.push_back(d);
    }
  }
  std::sort(out.begin(), out.end(),
            [](const Detection& a, const Detection& b) { return a.score > b.score; });
  if (int(out.size()) > max_detections) out.resize(std::max(0, max_detections));
  return out;
}

ColorImage DetectorInput(const ColorImage& image) {
  ColorImage small(kDetectorInputWidth, kDetectorInputHeight);
  if (image.empty()) return small;
  const cv::Mat src(image.height, image.width, CV_8UC3,
                    const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat dst(small.height, small.width, CV_8UC3, small.data.data());
  cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
  return small;
}

namespace {

/// Walks the top level of an ONNX file's protobuf encoding (ModelProto): every
/// field must be well formed and inside the file, and the graph (field 7) must
/// be there. OpenCV 4.6's importer can corrupt the heap on garbage, so garbage
/// and truncated files are refused before it sees them.
bool LooksLikeOnnx(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  auto varint = [&](std::uint64_t* value) {
    *value = 0;
    for (int shift = 0; shift < 64 && pos < bytes.size(); shift += 7) {
      const auto b = static_cast<std::uint8_t>(bytes[pos++]);
      *value |= std::uint64_t(b & 0x7F) << shift;
      if (!(b & 0x80)) return true;
    }
    return false;
  };
  bool has_graph = false;
  while (pos < bytes.size()) {
    std::uint64_t key = 0, value = 0;
    if (!varint(&key) || (key >> 3) == 0) return false;
    switch (key & 7) {
      case 0:
        if (!varint(&value)) return false;
        break;
      case 1:
        pos += 8;
        break;
      case 2:
        if (!varint(&value) || value > bytes.size() - pos) return false;
        pos += value;
        has_graph = has_graph || (key >> 3) == 7;
        break;
      case 5:
        pos += 4;
        break;
      default:
        return false;
    }
    if (pos > bytes.size()) return false;
  }
  return has_graph;
}

}  // namespace

struct BoxDetector::Impl {
  cv::dnn::Net net;
};

BoxDetector::BoxDetector(const std::string& onnx_path) : impl_(new Impl), path_(onnx_path) {
  if (!std::filesystem::is_regular_file(onnx_path))
    throw std::runtime_error(onnx_path + ": no such detector model");
  if (!LooksLikeOnnx(onnx_path)) {
    throw std::runtime_error(
        onnx_path + ": cannot load the detector model: not an ONNX file (corrupt or truncated)");
  }
  try {
    impl_->net = cv::dnn::readNetFromONNX(onnx_path);
    impl_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    impl_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    // One dry run checks the output shape.
    const int shape[4] = {1, 3, kDetectorInputHeight, kDetectorInputWidth};
    cv::Mat blob(4, shape, CV_32F, cv::Scalar(0));
    impl_->net.setInput(blob);
    const cv::Mat out = impl_->net.forward();
    if (out.dims != 4 || out.size[1] != 5 ||
        out.size[2] != kDetectorInputHeight / kDetectorStride ||
        out.size[3] != kDetectorInputWidth / kDetectorStride) {
      throw std::runtime_error(onnx_path + ": detector output must be 1x5x30x40");
    }
  } catch (const cv::Exception& e) {
    throw std::runtime_error(onnx_path + ": cannot load the detector model: " + e.what());
  }
}

BoxDetector::~BoxDetector() = default;

std::vector<Detection> BoxDetector::Detect(const ColorImage& image, float min_score) {
  if (image.empty()) return {};
  const ColorImage small = DetectorInput(image);
  const cv::Mat rgb(small.height, small.width, CV_8UC3,
                    const_cast<std::uint8_t*>(small.data.data()));
  const cv::Mat blob =
      cv::dnn::blobFromImage(rgb, 1.0 / 255.0, cv::Size(), cv::Scalar(), false, false, CV_32F);
  impl_->net.setInput(blob);
  const cv::Mat out = impl_->net.forward();
  CenterNetMaps maps;
  maps.width = out.size[3];
  maps.height = out.size[2];
  const std::size_t n = std::size_t(maps.width) * maps.height;
  const float* data = out.ptr<float>();
  std::vector<float>* channels[5] = {&maps.heat_logit, &maps.offset_x, &maps.offset_y,
                                     &maps.log_width, &maps.log_height};
  for (int c = 0; c < 5; ++c) channels[c]->assign(data + c * n, data + (c + 1) * n);
  return DecodeCenterNet(maps, image.width, image.height, min_score);
}

}  // namespace aerograsp
