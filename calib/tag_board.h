// AprilTag boards: their definition, a printable picture, detection with
// libapriltag, and the board's pose from all detected corners (ViSP vpPose).
//
// Board frame t: origin at the centre of the board's printed face, x to the
// right and y down as printed, z = x cross y into the board (away from a
// viewer who can read it). Tags are laid out row by row from the top left,
// ids first_id, first_id + 1, ...
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/camera_model.h"
#include "core/config.h"
#include "core/image.h"

namespace aerograsp {

struct TagBoardConfig {
  std::string family{"tag36h11"};  ///< only tag36h11 is supported
  int rows{2};                     ///< [1, 20]
  int cols{3};                     ///< [1, 20]
  double tag_size_m{0.018};        ///< edge of a tag's black square, (0.005, 1] m
  double spacing_m{0.006};         ///< white gap between neighbouring tags, [0, 1] m
  double margin_m{0.004};          ///< white border around the tags, [0, 1] m
  int first_id{0};                 ///< id of the top-left tag, [0, 586 - rows * cols]

  /// Reads the fields present in `node` (unknown keys are rejected).
  static TagBoardConfig FromNode(const ConfigNode& node);
  /// @throws ConfigError naming `source`, the key (under `prefix`) and the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
  /// Width and height of the printed board, m.
  Eigen::Vector2d Size() const;
};

/// One tag's black-square corners in t, in the order top-left, top-right,
/// bottom-right, bottom-left as printed.
struct BoardTag {
  int id = 0;
  std::array<Eigen::Vector3d, 4> corners_t;
};
std::vector<BoardTag> BoardTags(const TagBoardConfig& board);

/// The printed board as an RGB image, `px_per_m` pixels per metre; pixel
/// (u, v) is at t = (u / px_per_m - width / 2, v / px_per_m - height / 2, 0).
ColorImage RenderBoardImage(const TagBoardConfig& board, double px_per_m);

/// Writes the board as an SVG at true scale (millimetres).
/// @throws std::runtime_error naming the file when it cannot be written.
void WriteBoardSvg(const TagBoardConfig& board, const std::string& path);

/// A detected tag, corners in the same order as BoardTag (pixels).
struct TagDetection {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners_px;
  double decision_margin = 0.0;
};

/// libapriltag's detector for one family (pimpl; not thread-safe).
class TagDetector {
 public:
  /// @throws std::invalid_argument for an unsupported family.
  explicit TagDetector(const std::string& family = "tag36h11");
  ~TagDetector();
  TagDetector(const TagDetector&) = delete;
  TagDetector& operator=(const TagDetector&) = delete;
  /// Tags found in an RGB image (only those with no corrected bit errors).
  std::vector<TagDetection> Detect(const ColorImage& image);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A board corner seen in an image: the point in t and its pixel.
using BoardCorner = std::pair<Eigen::Vector3d, Eigen::Vector2d>;

/// The corners of the detections that belong to the board (others ignored),
/// each with its place on the board; `tags_used`, when given, receives how many
/// detections belonged to the board.
std::vector<BoardCorner> MatchBoardCorners(const std::vector<TagDetection>& detections,
                                           const TagBoardConfig& board, int* tags_used = nullptr);

struct BoardPose {
  bool valid = false;
  Eigen::Isometry3d cMt = Eigen::Isometry3d::Identity();
  int tags_used = 0;               ///< detections that belong to the board
  double reprojection_rms_px = 0;  ///< of all used corners
};

/// The board's pose from every detected corner of its tags (others ignored),
/// by ViSP's vpPose (Lagrange, which handles planar targets, then virtual
/// visual servoing).
/// Invalid when no tag of the board is seen.
BoardPose EstimateBoardPose(const std::vector<TagDetection>& detections,
                            const TagBoardConfig& board, const CameraIntrinsics& K);

}  // namespace aerograsp
