// `aerograsp calibrate --intrinsics`: the camera's intrinsics from views of a
// tag board, to check the factory values; `--resolve DIR` solves again from
// the saved views.
#pragma once

#include <ostream>
#include <string>

#include "app/calibrate_command.h"
#include "calib/tag_board.h"

namespace aerograsp {

/// The board the intrinsics wizard shows: 4 x 5 tag36h11 tags of 30 mm
/// (0.202 x 0.164 m): 80 corners, half the image's width at 0.4 m.
TagBoardConfig IntrinsicsBoard();

/// Shows the board to the camera in `options.poses` planned views (in the
/// simulator a hand holds it 0.28-0.55 m in front of the camera, tilted 20-45
/// deg about axes spread around the optical axis, its centre anywhere in the
/// image), detects its corners, rejects views with fewer than half its tags,
/// solves with OpenCV's calibrateCamera (calib/intrinsics_calibration.h),
/// rejects views whose error stands out and solves again, and writes
/// DIR/views/NNN.png, DIR/views.yaml (the views, for --resolve),
/// DIR/intrinsics.yaml, DIR/camera.xml (ViSP's camera XML) and DIR/summary.json
/// with the difference to the camera's own (factory) intrinsics.
/// @throws ConfigError for bad options or hardware; std::runtime_error when
/// fewer than 4 views are usable (the views stay on disk).
void RunCalibrateIntrinsics(const CalibrateCommandOptions& options, std::ostream& out,
                            std::ostream& progress);

/// Whether `folder` holds an intrinsics run's views (views.yaml).
bool IsIntrinsicsFolder(const std::string& folder);

/// Solves again from `folder`/views.yaml and rewrites the results.
/// @throws ConfigError "<folder>/views.yaml: <key>: ..." for a malformed file.
void ResolveIntrinsics(const std::string& folder, std::ostream& out);

}  // namespace aerograsp
