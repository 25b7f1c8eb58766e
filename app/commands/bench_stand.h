// The bench's test stand: the tag board on the object (the `bench` section
// of a hardware file), the object's scripted path in the in-process
// simulator, and which devices the bench can run with.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "calib/tag_board.h"
#include "core/mesh.h"
#include "hardware/hardware_config.h"

namespace aerograsp {

/// The bench's board: one row of three 36 mm tags (44 x 132 mm), which fits
/// the crawler's 60 mm recess between its tracks and resolves at 0.5 m.
TagBoardConfig BenchBoard();
/// The board centred on the object's top (over its bounding-box centre),
/// printed face up (+z_o; t's z points into the board, so z_t = -z_o), x_t along x_o.
Eigen::Isometry3d DefaultBoardOnObject(const TriangleMesh& mesh_o);

/// The `bench` section of a hardware file: the board printed and where it is
/// fixed on the object (data/config/hardware_example.yaml documents each key).
/// With a simulated camera the simulated world carries the board there; with
/// the real one, it is where the person fixed it.
struct BenchRig {
  std::string source;                   ///< the hardware file (for messages)
  TagBoardConfig board = BenchBoard();  ///< the printed board
  /// The board on the object, oMt; empty: DefaultBoardOnObject.
  std::optional<Eigen::Isometry3d> oMt;

  /// The defaults when the file has no `bench` section.
  /// @throws ConfigError "<file>: bench.<key>: ..." for unknown keys and bounds.
  static BenchRig Load(const std::string& hardware_path);
  /// @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};
/// The scripted path of the object in the body frame d (the in-process
/// simulator only): upright (z_o up, x_o across the vehicle along y_d, as on
/// the mission's pipe), its bounding-box centre `centre_o` around the mission's
/// grasp point `grasp_dto_m`. At scale 1: +-0.06 m fore and aft (the arms reach
/// top-down grasps only about 0.04-0.11 m ahead, so part of the time), +-0.02 m
/// sideways, +-0.02 m up and down and +-0.1 rad of yaw.
Eigen::Isometry3d ScriptedDmo(double t_s, double period_s, double scale,
                              const Eigen::Vector3d& grasp_dto_m, const Eigen::Vector3d& centre_o);
/// The object must be in front of the camera that is used and the arms must
/// reach what that camera sees: real arms ('scs') need the real camera; the
/// simulated camera needs a simulated vehicle; a recording cannot be servoed to.
/// @throws ConfigError "<file>: <key>: '<backend>': <why>; <what to use>".
void CheckBenchHardware(const HardwareConfig& config);

}  // namespace aerograsp
