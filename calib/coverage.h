// Coverage of a camera calibration's samples: which parts of the image the
// board's corners have reached and which tilts of the board have been shown,
// to tell the person holding the board what is still missing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace aerograsp {

class ConfigNode;

struct CoverageConfig {
  int grid_cols = 3;             ///< image cells across, [1, 8]
  int grid_rows = 3;             ///< image cells down, [1, 8]
  int min_corners_per_cell = 4;  ///< corners of one sample that cover a cell, [1, 1000]
  double min_tilt_deg = 20.0;    ///< tilt about x or y (each sign) still missing below this, deg
                                 ///< [1, 80]

  /// Reads the fields present in `node` (unknown keys are rejected) and validates them.
  static CoverageConfig FromNode(const ConfigNode& node);
  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// One sample of the board: its corners in the image (px) and its tilt about
/// the camera's x and y axes (deg; 0 facing the camera, the sign the side
/// that comes closer: +x its top edge away, +y its left edge closer).
struct CoverageSample {
  std::vector<Eigen::Vector2d> pixels;
  double tilt_x_deg = 0.0;
  double tilt_y_deg = 0.0;
};

/// The tilt bins: about x and y, each sign.
enum class TiltBin { kXPositive = 0, kXNegative = 1, kYPositive = 2, kYNegative = 3 };

/// What a set of samples covers.
struct Coverage {
  int cols = 0, rows = 0;
  std::vector<int> cell_samples;       ///< per cell (row-major): samples that cover it
  int tilt_samples[4] = {0, 0, 0, 0};  ///< per TiltBin
  /// Per sample, its signature: the cell of the board's centre and its tilt bins
  /// about x and y (-1, 0, +1); two samples of one signature add little.
  std::vector<Eigen::Vector3i> signatures;
  bool Complete() const;
};

/// The cells `sample` covers (row-major indices), its tilt bins and its signature.
struct SampleCoverage {
  std::vector<int> cells;
  std::vector<TiltBin> tilts;
  Eigen::Vector3i signature{0, 0, 0};
};

/// The coverage of one sample in a `width` x `height` image (pixels outside are ignored).
SampleCoverage CoverSample(const CoverageSample& sample, int width, int height,
                           const CoverageConfig& config);

/// An empty coverage of the config's grid.
Coverage EmptyCoverage(const CoverageConfig& config);

/// Whether `sample` adds something to `coverage`: a cell or a tilt bin not yet
/// covered, or a signature (centre cell, tilt bins) no sample has yet.
bool AddsToCoverage(const Coverage& coverage, const SampleCoverage& sample);

/// `coverage` with `sample` added.
void AddToCoverage(const SampleCoverage& sample, Coverage* coverage);

/// One line for the person holding the board: "missing: top-left, bottom-right;
/// tilt about x > 20 deg, tilt about y < -20 deg", or "complete" when nothing is.
/// On a 3 x 3 grid the cells are named top-left, top, top-right, left, centre,
/// right, bottom-left, bottom, bottom-right; on other grids "row R col C" (from 1).
std::string CoverageFeedback(const Coverage& coverage, const CoverageConfig& config);

/// Whether the board stood still between two frames: the same corners (same
/// count) none of which moved more than `max_motion_px`.
bool BoardStill(const std::vector<Eigen::Vector2d>& previous_px,
                const std::vector<Eigen::Vector2d>& current_px, double max_motion_px);

}  // namespace aerograsp
