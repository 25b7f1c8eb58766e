// What a mission leaves behind for its report: samples of the estimated and
// true object pose, the joints' targets and actual positions, the vehicle, the
// state machines' transitions with their causes, the grasp switches and one
// camera frame with its detection. Filled by the mission runner
// (app/runtime/mission_runner.h), drawn by app/report/mission_report.h.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/mesh.h"

namespace aerograsp {

struct FrameReport;

/// One log row (the runner writes one per camera frame).
struct MissionSample {
  double t_s = 0.0;  ///< simulated (or wall) mission time
  bool estimate_valid = false;
  /// The object in the body frame d (FRD): estimate (NaN when none) and truth
  /// (NaN on hardware, where there is none).
  Eigen::Vector3d dto_estimate_m = Eigen::Vector3d::Constant(NAN);
  Eigen::Vector3d dto_truth_m = Eigen::Vector3d::Constant(NAN);
  /// estimate vs truth (symmetry-aware), NaN when either is missing
  double rotation_error_deg = NAN;
  bool found = false;  ///< vision state found
  /// Per arm (0 left, 1 right): the joint targets sent and the joints measured, rad.
  Eigen::VectorXd q_target_rad[2];
  Eigen::VectorXd q_actual_rad[2];
  Eigen::Vector3d vehicle_w_m = Eigen::Vector3d::Zero();  ///< body position in w (NED)
};

/// A state machine changed state.
struct MissionTransition {
  double t_s = 0.0;
  std::string machine;  ///< "global", "vehicle", "vision", "planner", "arms"
  std::string from, to;
  std::string cause;  ///< the signal or condition, one line
};

/// The followed dual grasp changed (contact-pair indices per arm).
struct MissionGraspSwitch {
  double t_s = 0.0;
  int left_pair = -1, right_pair = -1;
  std::string reason;
};

/// One camera frame of the mission with what perception made of it.
struct MissionSnapshot {
  double t_s = 0.0;
  ColorImage color;
  CameraIntrinsics K;
  bool has_box = false;
  int box_x0 = 0, box_y0 = 0, box_x1 = 0, box_y1 = 0;  ///< detector box, pixels
  bool has_pose = false;
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();  ///< the estimate, to overlay the model
};

struct MissionRecord {
  std::string object_name;
  TriangleMesh object_mesh_o;               ///< for the camera overlay
  std::vector<std::string> joint_names[2];  ///< per arm, for plot labels
  std::vector<MissionSample> samples;
  std::vector<MissionTransition> transitions;
  std::vector<MissionGraspSwitch> switches;
  std::optional<MissionSnapshot> snapshot;
};

/// The report's camera frame: `color`, taken at `t_s` through `K`, with the
/// tracker's detector box and pose estimate of it (`report`).
MissionSnapshot FrameSnapshot(double t_s, const ColorImage& color, const CameraIntrinsics& K,
                              const FrameReport& report);

}  // namespace aerograsp
