// `aerograsp plan OBJECT --out DIR`: the ranked dual grasps of an object placed
// at a configurable pose in front of and below the vehicle, a picture of the
// best ones, the contact cache, and summary.json with the stage timings.
#pragma once

#include <Eigen/Core>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct PlanCommandOptions {
  std::string object;       ///< an object name (shipped or imported) or a mesh path
  std::string out_dir;      ///< summary.json and grasps.png go here (written aside, renamed)
  bool overwrite = false;   ///< replace a report already in out_dir
  std::string config_path;  ///< platform YAML
  /// Where the object is placed for planning: its bounding-box centre
  /// (PlacementCentre, the origin of o for the shipped objects) and the axes of
  /// o in the body frame d (FRD: x forward, y right, z down). Default: 0.10 m ahead of the body
  /// centre, centred between the arms, 0.46 m below it, upright (roll 180 deg
  /// turns the object's z-up into d's z-down) with its long x axis across the
  /// vehicle (yaw 90 deg) so each arm can take one end. Why there: the shoulders
  /// are at y = +-0.1525 m, z = 0.12 m, and the 4-DoF arm reaches forward only
  /// nearly stretched (yaw +-90 deg, elbow >= -15 deg), so its grasps lie about
  /// 0.3-0.44 m below the shoulders with a downward approach; the placement
  /// maximises the dual pairs of the shipped objects. Override with
  /// --object-xyz / --object-rpy.
  Eigen::Vector3d object_xyz_m{0.10, 0.0, 0.46};
  Eigen::Vector3d object_rpy_deg{180.0, 0.0, 90.0};  ///< URDF roll, pitch, yaw of o in d (deg)
  double resolution_m = 0.015;                       ///< contact ray grid (m)
  double depth_min_m = 0.0;  ///< contacts at least this far behind the tool point (m)
  /// robustness probe distance (m); GraspPlannerConfig::reach_margin_m
  double reach_margin_m = 0.0;
  /// contacts this far from their faces' edges rank first (m); GraspPlannerConfig::edge_margin_m
  double edge_margin_m = 0.0;
  /// Search where the mission holds the object (grasp/placement.h) around
  /// object_xyz_m, upright at object_rpy_deg's yaw, with the mission's planner
  /// and placement settings (mission_default.yaml), and plan there.
  bool place = false;
  double mass_kg = 0.5;  ///< used for a bare mesh (shipped objects carry theirs)
  /// contact cache folder; "" = $XDG_CACHE_HOME/aerograsp or ~/.cache/aerograsp
  std::string cache_dir;
  bool use_cache = true;
  int top = 10;     ///< rows of the table
  int repeats = 3;  ///< timing repetitions (median reported)
};

/// Runs the planner and prints the table; writes DIR/summary.json and
/// DIR/grasps.png. A plan with no feasible grasp is not an error: it prints
/// why (too big for the gripper, out of reach, collisions) and the summary says
/// so too.
/// @throws MeshError / ConfigError naming the file and what is wrong (missing,
/// corrupt or open mesh, bad object.yaml); std::runtime_error when DIR cannot
/// be written.
void RunPlanCommand(const PlanCommandOptions& options, std::ostream& out);

/// Adds `plan`'s options to `cmd` (a CLI11 subcommand); the object's position
/// and angles reach `options` when the command line has been parsed.
void AddPlanOptions(CLI::App* cmd, PlanCommandOptions* options);

}  // namespace aerograsp
