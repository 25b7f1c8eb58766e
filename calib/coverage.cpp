#include "calib/coverage.h"

#include <algorithm>
#include <cmath>

#include "core/config.h"

namespace aerograsp {

CoverageConfig CoverageConfig::FromNode(const ConfigNode& node) {
  node.RequireOnlyKeys({"grid_cols", "grid_rows", "min_corners_per_cell", "min_tilt_deg"});
  CoverageConfig c;
  c.grid_cols = node.GetInt("grid_cols", c.grid_cols);
  c.grid_rows = node.GetInt("grid_rows", c.grid_rows);
  c.min_corners_per_cell = node.GetInt("min_corners_per_cell", c.min_corners_per_cell);
  c.min_tilt_deg = node.GetDouble("min_tilt_deg", c.min_tilt_deg);
  c.Validate(node.source(), node.KeyPath(""));
  return c;
}

void CoverageConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "grid_cols", grid_cols, 1, 8, "");
  CheckRange(source, prefix + "grid_rows", grid_rows, 1, 8, "");
  CheckRange(source, prefix + "min_corners_per_cell", min_corners_per_cell, 1, 1000, "");
  CheckRange(source, prefix + "min_tilt_deg", min_tilt_deg, 1.0, 80.0, "deg");
}

bool Coverage::Complete() const {
  if (cell_samples.empty()) return false;
  for (int n : cell_samples)
    if (n == 0) return false;
  for (int n : tilt_samples)
    if (n == 0) return false;
  return true;
}

Coverage EmptyCoverage(const CoverageConfig& config) {
  Coverage c;
  c.cols = config.grid_cols;
  c.rows = config.grid_rows;
  c.cell_samples.assign(static_cast<std::size_t>(c.cols * c.rows), 0);
  return c;
}

SampleCoverage CoverSample(const CoverageSample& sample, int width, int height,
                           const CoverageConfig& config) {
  SampleCoverage result;
  const int cols = config.grid_cols, rows = config.grid_rows;
  auto cell_of = [&](const Eigen::Vector2d& px) {
    const int col = std::clamp(static_cast<int>(px.x() * cols / width), 0, cols - 1);
    const int row = std::clamp(static_cast<int>(px.y() * rows / height), 0, rows - 1);
    return row * cols + col;
  };
  std::vector<int> counts(static_cast<std::size_t>(cols * rows), 0);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int inside = 0;
  for (const Eigen::Vector2d& px : sample.pixels) {
    if (!(px.x() >= 0.0 && px.y() >= 0.0 && px.x() < width && px.y() < height)) continue;
    ++counts[static_cast<std::size_t>(cell_of(px))];
    sum += px;
    ++inside;
  }
  for (int i = 0; i < cols * rows; ++i) {
    if (counts[static_cast<std::size_t>(i)] >= config.min_corners_per_cell)
      result.cells.push_back(i);
  }
  auto bin = [&](double tilt_deg) {
    return tilt_deg >= config.min_tilt_deg ? 1 : tilt_deg <= -config.min_tilt_deg ? -1 : 0;
  };
  const int bx = bin(sample.tilt_x_deg), by = bin(sample.tilt_y_deg);
  if (bx > 0) result.tilts.push_back(TiltBin::kXPositive);
  if (bx < 0) result.tilts.push_back(TiltBin::kXNegative);
  if (by > 0) result.tilts.push_back(TiltBin::kYPositive);
  if (by < 0) result.tilts.push_back(TiltBin::kYNegative);
  result.signature = {inside > 0 ? cell_of(sum / inside) : -1, bx, by};
  return result;
}

bool AddsToCoverage(const Coverage& coverage, const SampleCoverage& sample) {
  for (int cell : sample.cells)
    if (coverage.cell_samples[static_cast<std::size_t>(cell)] == 0) return true;
  for (TiltBin t : sample.tilts)
    if (coverage.tilt_samples[static_cast<int>(t)] == 0) return true;
  return std::find(coverage.signatures.begin(), coverage.signatures.end(), sample.signature) ==
         coverage.signatures.end();
}

void AddToCoverage(const SampleCoverage& sample, Coverage* coverage) {
  for (int cell : sample.cells) ++coverage->cell_samples[static_cast<std::size_t>(cell)];
  for (TiltBin t : sample.tilts) ++coverage->tilt_samples[static_cast<int>(t)];
  coverage->signatures.push_back(sample.signature);
}

std::string CoverageFeedback(const Coverage& coverage, const CoverageConfig& config) {
  static const char* const kNames3x3[9] = {"top-left",    "top",    "top-right",
                                           "left",        "centre", "right",
                                           "bottom-left", "bottom", "bottom-right"};
  std::string cells, tilts;
  for (int i = 0; i < coverage.cols * coverage.rows; ++i) {
    if (coverage.cell_samples[static_cast<std::size_t>(i)] > 0) continue;
    const std::string name = coverage.cols == 3 && coverage.rows == 3
                                 ? std::string(kNames3x3[i])
                                 : "row " + std::to_string(i / coverage.cols + 1) + " col " +
                                       std::to_string(i % coverage.cols + 1);
    cells += (cells.empty() ? "" : ", ") + name;
  }
  const std::string deg = std::to_string(static_cast<int>(std::lround(config.min_tilt_deg)));
  const std::string kTilts[4] = {
      "tilt about x > " + deg + " deg", "tilt about x < -" + deg + " deg",
      "tilt about y > " + deg + " deg", "tilt about y < -" + deg + " deg"};
  for (int t = 0; t < 4; ++t) {
    if (coverage.tilt_samples[t] > 0) continue;
    tilts += (tilts.empty() ? "" : ", ") + kTilts[t];
  }
  if (cells.empty() && tilts.empty()) return "complete";
  return "missing: " + cells + (!cells.empty() && !tilts.empty() ? "; " : "") + tilts;
}

bool BoardStill(const std::vector<Eigen::Vector2d>& previous_px,
                const std::vector<Eigen::Vector2d>& current_px, double max_motion_px) {
  if (previous_px.empty() || previous_px.size() != current_px.size()) return false;
  for (std::size_t i = 0; i < current_px.size(); ++i) {
    if ((current_px[i] - previous_px[i]).norm() > max_motion_px) return false;
  }
  return true;
}

}  // namespace aerograsp
