// Camera intrinsics from views of a planar tag board (Zhang's method, as
// OpenCV's calibrateCamera implements it): the pinhole focal lengths and
// principal point, and the radial-tangential distortion, to check a camera's
// factory values.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "calib/tag_board.h"
#include "core/camera_model.h"

namespace aerograsp {

/// One view of the board: its corners (point in t, pixel), at least 4.
struct IntrinsicsView {
  std::vector<BoardCorner> corners;
};

struct IntrinsicsResult {
  bool ok = false;
  std::string message;  ///< why it failed
  CameraIntrinsics K;   ///< fx, fy, cx, cy in pixels; width and height as given
  /// OpenCV's order: k1, k2, p1, p2, k3 (k3 is held at 0: see CalibrateIntrinsics).
  std::array<double, 5> distortion{};
  double rms_px = 0.0;                  ///< over every corner of every view
  std::vector<double> per_view_rms_px;  ///< one per view, in the order given
};

/// Solves for fx, fy, cx, cy, k1, k2, p1, p2 from `views` of a planar board
/// (every corner with z_t = 0), images `width` x `height` px. k3 is fixed at 0:
/// with a handful of views of a board that does not reach the image corners it
/// is not observable and only trades off with k1, k2. Needs views at several
/// tilts (parallel boards leave the focal length undetermined).
/// Not ok (with the reason) for fewer than `min_views` views, a non-planar
/// board, or a solve that OpenCV rejects.
IntrinsicsResult CalibrateIntrinsics(const std::vector<IntrinsicsView>& views, int width,
                                     int height, int min_views = 4);

}  // namespace aerograsp
