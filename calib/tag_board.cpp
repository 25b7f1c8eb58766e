#include "calib/tag_board.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <visp3/core/vpPoint.h>
#include <visp3/vision/vpPose.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <stdexcept>

#include "core/conversions.h"

namespace aerograsp {

TagBoardConfig TagBoardConfig::FromNode(const ConfigNode& node) {
  node.RequireOnlyKeys(
      {"family", "rows", "cols", "tag_size_m", "spacing_m", "margin_m", "first_id"});
  TagBoardConfig c;
  c.family = node.GetString("family", c.family);
  c.rows = node.GetInt("rows", c.rows);
  c.cols = node.GetInt("cols", c.cols);
  c.tag_size_m = node.GetDouble("tag_size_m", c.tag_size_m);
  c.spacing_m = node.GetDouble("spacing_m", c.spacing_m);
  c.margin_m = node.GetDouble("margin_m", c.margin_m);
  c.first_id = node.GetInt("first_id", c.first_id);
  c.Validate(node.source(), node.KeyPath(""));
  return c;
}

void TagBoardConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckOneOf(source, prefix + "family", family, {"tag36h11"});
  CheckRange(source, prefix + "rows", rows, 1, 20, "");
  CheckRange(source, prefix + "cols", cols, 1, 20, "");
  CheckRange(source, prefix + "tag_size_m", tag_size_m, 0.005, 1.0, "m");
  CheckRange(source, prefix + "spacing_m", spacing_m, 0.0, 1.0, "m");
  CheckRange(source, prefix + "margin_m", margin_m, 0.0, 1.0, "m");
  CheckRange(source, prefix + "first_id", first_id, 0, 587 - rows * cols, "");
}

Eigen::Vector2d TagBoardConfig::Size() const {
  return {cols * tag_size_m + (cols - 1) * spacing_m + 2 * margin_m,
          rows * tag_size_m + (rows - 1) * spacing_m + 2 * margin_m};
}

std::vector<BoardTag> BoardTags(const TagBoardConfig& board) {
  const Eigen::Vector2d half = 0.5 * board.Size();
  std::vector<BoardTag> tags;
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c) {
      BoardTag tag;
      tag.id = board.first_id + r * board.cols + c;
      const double x0 = board.margin_m + c * (board.tag_size_m + board.spacing_m) - half.x();
      const double y0 = board.margin_m + r * (board.tag_size_m + board.spacing_m) - half.y();
      const double s = board.tag_size_m;
      tag.corners_t = {Eigen::Vector3d(x0, y0, 0), Eigen::Vector3d(x0 + s, y0, 0),
                       Eigen::Vector3d(x0 + s, y0 + s, 0), Eigen::Vector3d(x0, y0 + s, 0)};
      tags.push_back(tag);
    }
  }
  return tags;
}

namespace {

/// The black-and-white cells of one tag including its white border:
/// total_width x total_width, true = black.
std::vector<std::vector<bool>> TagCells(int id, int* black_width) {
  apriltag_family_t* family = tag36h11_create();
  image_u8_t* image = apriltag_to_image(family, id);
  const int border = (family->total_width - family->width_at_border) / 2;
  *black_width = family->width_at_border;
  std::vector<std::vector<bool>> cells(family->width_at_border,
                                       std::vector<bool>(family->width_at_border));
  for (int y = 0; y < family->width_at_border; ++y) {
    for (int x = 0; x < family->width_at_border; ++x) {
      cells[y][x] = image->buf[(y + border) * image->stride + x + border] < 128;
    }
  }
  // Debian's libapriltag does not export image_u8_destroy; the image and its
  // buffer come from calloc.
  std::free(image->buf);
  std::free(image);
  tag36h11_destroy(family);
  return cells;
}

}  // namespace

ColorImage RenderBoardImage(const TagBoardConfig& board, double px_per_m) {
  const Eigen::Vector2d size = board.Size();
  const int width = static_cast<int>(std::lround(size.x() * px_per_m));
  const int height = static_cast<int>(std::lround(size.y() * px_per_m));
  ColorImage image(width, height, 255);
  for (const BoardTag& tag : BoardTags(board)) {
    int cells_across = 0;
    const auto cells = TagCells(tag.id, &cells_across);
    const double x0 = (tag.corners_t[0].x() + 0.5 * size.x()) * px_per_m;
    const double y0 = (tag.corners_t[0].y() + 0.5 * size.y()) * px_per_m;
    const double cell_px = board.tag_size_m * px_per_m / cells_across;
    for (int v = std::max(0, int(y0));
         v < std::min(height, int(std::ceil(y0 + cells_across * cell_px))); ++v) {
      for (int u = std::max(0, int(x0));
           u < std::min(width, int(std::ceil(x0 + cells_across * cell_px))); ++u) {
        const int cx = static_cast<int>((u + 0.5 - x0) / cell_px),
                  cy = static_cast<int>((v + 0.5 - y0) / cell_px);
        if (cx < 0 || cy < 0 || cx >= cells_across || cy >= cells_across || !cells[cy][cx])
          continue;
        for (int c = 0; c < 3; ++c) image.at(u, v, c) = 0;
      }
    }
  }
  return image;
}

void WriteBoardSvg(const TagBoardConfig& board, const std::string& path) {
  const Eigen::Vector2d size_mm = 1e3 * board.Size();
  std::ofstream out(path);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size_mm.x() << "mm\" height=\""
      << size_mm.y() << "mm\" viewBox=\"0 0 " << size_mm.x() << " " << size_mm.y() << "\">\n"
      << "<!-- aerograsp tag board: " << board.family << ", " << board.rows << " x " << board.cols
      << " tags of " << 1e3 * board.tag_size_m << " mm, ids from " << board.first_id
      << ". Print at 100 % scale. -->\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const Eigen::Vector2d half = 0.5 * board.Size();
  for (const BoardTag& tag : BoardTags(board)) {
    int cells_across = 0;
    const auto cells = TagCells(tag.id, &cells_across);
    const double cell_mm = 1e3 * board.tag_size_m / cells_across;
    const double x0 = 1e3 * (tag.corners_t[0].x() + half.x()),
                 y0 = 1e3 * (tag.corners_t[0].y() + half.y());
    for (int cy = 0; cy < cells_across; ++cy) {
      for (int cx = 0; cx < cells_across; ++cx) {
        if (!cells[cy][cx]) continue;
        out << "<rect x=\"" << x0 + cx * cell_mm << "\" y=\"" << y0 + cy * cell_mm << "\" width=\""
            << cell_mm << "\" height=\"" << cell_mm << "\" fill=\"black\"/>\n";
      }
    }
  }
  out << "</svg>\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

struct TagDetector::Impl {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
};

TagDetector::TagDetector(const std::string& family) : impl_(std::make_unique<Impl>()) {
  if (family != "tag36h11")
    throw std::invalid_argument("tag family '" + family + "' is not supported (tag36h11)");
  impl_->family = tag36h11_create();
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family(impl_->detector, impl_->family);
  impl_->detector->nthreads = 1;
  impl_->detector->quad_decimate = 1.0f;  // small tags on the gripper: full resolution
  impl_->detector->refine_edges = 1;
}

TagDetector::~TagDetector() {
  apriltag_detector_destroy(impl_->detector);
  tag36h11_destroy(impl_->family);
}

std::vector<TagDetection> TagDetector::Detect(const ColorImage& image) {
  std::vector<std::uint8_t> luminance(static_cast<std::size_t>(image.width) * image.height);
  for (std::size_t i = 0; i < luminance.size(); ++i) {
    const std::uint8_t* p = &image.data[3 * i];
    luminance[i] = static_cast<std::uint8_t>((77 * p[0] + 150 * p[1] + 29 * p[2]) >> 8);
  }
  image_u8_t gray = {image.width, image.height, image.width, luminance.data()};
  zarray_t* found = apriltag_detector_detect(impl_->detector, &gray);
  std::vector<TagDetection> detections;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(found, i, &det);
    if (det->hamming != 0) continue;
    TagDetection d;
    d.id = det->id;
    d.decision_margin = det->decision_margin;
    // libapriltag's corners wrap bottom-left, bottom-right, top-right,
    // top-left (ideal corners (-1, 1), (1, 1), (1, -1), (-1, -1), y down);
    // ours start at the top left.
    const int order[4] = {3, 2, 1, 0};
    for (int k = 0; k < 4; ++k)
      d.corners_px[k] = Eigen::Vector2d(det->p[order[k]][0], det->p[order[k]][1]);
    detections.push_back(d);
  }
  apriltag_detections_destroy(found);
  return detections;
}

std::vector<BoardCorner> MatchBoardCorners(const std::vector<TagDetection>& detections,
                                           const TagBoardConfig& board, int* tags_used) {
  std::map<int, const BoardTag*> by_id;
  const std::vector<BoardTag> tags = BoardTags(board);
  for (const BoardTag& t : tags) by_id[t.id] = &t;
  std::vector<BoardCorner> matches;
  int used = 0;
  for (const TagDetection& d : detections) {
    const auto it = by_id.find(d.id);
    if (it == by_id.end()) continue;
    ++used;
    for (int k = 0; k < 4; ++k) matches.emplace_back(it->second->corners_t[k], d.corners_px[k]);
  }
  if (tags_used) *tags_used = used;
  return matches;
}

BoardPose EstimateBoardPose(const std::vector<TagDetection>& detections,
                            const TagBoardConfig& board, const CameraIntrinsics& K) {
  BoardPose result;
  const std::vector<BoardCorner> matches = MatchBoardCorners(detections, board, &result.tags_used);
  if (matches.size() < 4) return result;
  vpPose pose;
  for (const auto& [p_t, px] : matches) {
    vpPoint point(p_t.x(), p_t.y(), p_t.z());
    point.set_x((px.x() - K.cx) / K.fx);
    point.set_y((px.y() - K.cy) / K.fy);
    pose.addPoint(point);
  }
  vpHomogeneousMatrix cMt;
  try {
    if (!pose.computePose(vpPose::LAGRANGE_VIRTUAL_VS, cMt)) return result;
  } catch (const vpException&) {
    return result;  // degenerate point set
  }
  result.cMt = FromVisp(cMt);
  double sq = 0.0;
  for (const auto& [p_t, px] : matches) {
    const Eigen::Vector3d p_c = result.cMt * p_t;
    if (p_c.z() <= 0.0) return result;
    sq += (K.Project(p_c) - px).squaredNorm();
  }
  result.reprojection_rms_px = std::sqrt(sq / matches.size());
  result.valid = true;
  return result;
}

}  // namespace aerograsp
