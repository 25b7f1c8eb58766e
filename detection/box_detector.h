// The single-class CNN detector (docs/perception.md, The detector): a CenterNet-style
// network trained by tools/train_detector.py, run with OpenCV's dnn on a
// 160x120 RGB input; its one output holds, per cell of a 40x30 grid, the
// centre-heatmap logit, the sub-cell offset of the centre and the log box size.
// Decoding (peak finding, sigmoid, boxes) is ours, in C++, because OpenCV 4.6
// dnn cannot run TopK/Where; it is a free function so tests can feed it maps.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "detection/scene_cloud.h"

namespace aerograsp {

/// The network input size (pixels) and its output stride.
inline constexpr int kDetectorInputWidth = 160;
inline constexpr int kDetectorInputHeight = 120;
inline constexpr int kDetectorStride = 4;

struct Detection {
  PixelBox box;        ///< in the pixels of the full image
  float score = 0.0f;  ///< sigmoid of the heatmap peak, [0, 1]
};

/// The raw head: five width x height maps, row-major.
struct CenterNetMaps {
  int width = 0, height = 0;
  std::vector<float> heat_logit;  ///< centre heatmap before the sigmoid
  std::vector<float> offset_x;    ///< centre offset within its cell, cells
  std::vector<float> offset_y;
  std::vector<float> log_width;  ///< log of the box width in cells
  std::vector<float> log_height;
};

/// Peaks of the heatmap (3x3 local maxima with sigmoid >= min_score), best
/// first, at most max_detections, decoded to boxes in an image of
/// image_width x image_height (one cell = image_width / maps.width pixels).
/// Maps of inconsistent sizes or non-finite values give no detections.
std::vector<Detection> DecodeCenterNet(const CenterNetMaps& maps, int image_width, int image_height,
                                       float min_score, int max_detections = 5);

/// The network input: the image resized to 160x120 (area averaging), RGB. The
/// dataset command writes exactly this, so training and inference agree.
ColorImage DetectorInput(const ColorImage& image);

class BoxDetector {
 public:
  /// Loads an ONNX model. @throws std::runtime_error naming the file when it is
  /// missing or OpenCV cannot load it, or its output has the wrong shape.
  explicit BoxDetector(const std::string& onnx_path);
  ~BoxDetector();
  BoxDetector(const BoxDetector&) = delete;
  BoxDetector& operator=(const BoxDetector&) = delete;

  /// Detections in `image`, best first. An empty image gives none.
  std::vector<Detection> Detect(const ColorImage& image, float min_score = 0.3f);
  const std::string& path() const { return path_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
};

}  // namespace aerograsp
