// The bench's test stand: the tag board on the object, the object's
// scripted path in the simulator, and which devices the bench can run with.
#pragma once

#include <Eigen/Geometry>

#include "calib/tag_board.h"
#include "core/mesh.h"
#include "hardware/hardware_config.h"

namespace aerograsp {

/// The bench's board: one row of three 36 mm tags (44 x 132 mm), which fits
/// the crawler's 60 mm recess between its tracks and resolves at 0.5 m.
TagBoardConfig BenchBoard();
/// The board centred on the object's top, printed face up (+z_o; t's z points
/// into the board, so z_t = -z_o), x_t along x_o.
Eigen::Isometry3d DefaultBoardOnObject(const TriangleMesh& mesh_o);
/// The scripted path of the object in the body frame d: upright (z_o up, x_o
/// across the vehicle along y_d, as on the mission's pipe), around the
/// mission's grasp point grasp_dto_m. At scale 1: +-0.06 m fore and aft (the
/// arms reach top-down grasps only about 0.04-0.11 m ahead, so part of the
/// time), +-0.02 m sideways, +-0.02 m up and down and +-0.1 rad of yaw.
Eigen::Isometry3d ScriptedDmo(double t_s, double period_s, double scale);
/// The bench needs a world it can move the object in and a camera that sees
/// that world; say what does not fit instead of faking it.
void CheckBenchHardware(const HardwareConfig& config);

}  // namespace aerograsp
