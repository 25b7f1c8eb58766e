// The intrinsics wizards' views (each image's board corners) and their file,
// DIR/views.yaml, which `calibrate --resolve DIR` solves again; the solve
// (outlier views rejected and solved again) and what it writes.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "calib/tag_board.h"
#include "core/camera_model.h"

namespace aerograsp {

/// Fewest usable views the intrinsics solve takes.
constexpr int kMinIntrinsicsViews = 4;

/// One view of the board.
struct SavedView {
  std::string image;  ///< relative to the output folder
  int tags_used = 0;
  bool accepted = false;
  std::string reject_reason;
  std::vector<BoardCorner> corners;
};

/// What DIR/views.yaml holds.
struct ViewsFile {
  TagBoardConfig board;
  /// The camera's own intrinsics; in simulation the truth.
  CameraIntrinsics factory;
  /// The platform's name for the camera in camera XML (platform.h: camera_name).
  std::string camera_name{"Camera"};
  bool simulated = false;
  std::vector<SavedView> views;
};

/// `folder`/views.yaml.
std::string ViewsPath(const std::string& folder);
/// Writes `file` to ViewsPath(folder). @throws std::runtime_error naming the file.
void WriteViewsYaml(const std::string& folder, const ViewsFile& file);
/// Reads ViewsPath(folder). @throws ConfigError "<folder>/views.yaml: <key>: ...".
ViewsFile ReadViewsYaml(const std::string& folder);
/// Solves from the accepted views (outliers rejected in `file`, then solved
/// again), prints the comparison with the factory intrinsics and writes
/// views.yaml, intrinsics.yaml, camera.xml and summary.json in `folder`.
/// @throws std::runtime_error when fewer than kMinIntrinsicsViews views are usable.
void SolveIntrinsicsAndReport(const std::string& folder, ViewsFile* file, std::ostream& out);

}  // namespace aerograsp
