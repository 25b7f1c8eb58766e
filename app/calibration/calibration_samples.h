// What the calibration wizards (hand-eye and intrinsics) save so that
// `aerograsp calibrate --resolve DIR` can solve again: the board, each view's
// image and its corners. yaml-cpp stays in the .cpp files.
#pragma once

#include <string>
#include <vector>

#include "calib/tag_board.h"
#include "core/config.h"
#include "core/image.h"

namespace YAML {
class Emitter;
class Node;
}  // namespace YAML

namespace aerograsp {

/// The board's fields as a YAML map (read back by TagBoardConfig::FromNode).
void EmitTagBoard(const TagBoardConfig& board, YAML::Emitter* y);
/// Corners as a list of [x_t, y_t, z_t, u_px, v_px].
void EmitCorners(const std::vector<BoardCorner>& corners, YAML::Emitter* y);
/// Reads EmitCorners' list. @throws ConfigError "<file>: <where>: ..." naming
/// the entry that is not five numbers.
std::vector<BoardCorner> ReadCorners(const YAML::Node& list, const ConfigNode& file,
                                     const std::string& where);

/// Writes an RGB image as a PNG. @throws std::runtime_error naming the file.
void WriteColorPng(const ColorImage& rgb, const std::string& path);

}  // namespace aerograsp
