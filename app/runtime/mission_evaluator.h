// What a simulated mission is measured against: the simulated world's truth.
// Attached to the world by the mission runner, which tells it what happened
// (a frame taken, a frame's estimate, a gripper closing) and never reads it
// for a decision. It fills the truth columns of the report's samples, counts
// safe-volume entries and arm contacts by the true joints, logs and keeps where
// the grippers close on the true object and gives the result's truth figures
// (pose RMSE, the closes, both grippers holding).
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "app/runtime/mission_record.h"
#include "app/runtime/mission_runner.h"
#include "core/platform.h"
#include "detection/model_cloud.h"

namespace aerograsp {

class World;
class PlatformCollision;

/// The closing gripper as the robot sees it.
struct ClosingView {
  Eigen::Isometry3d dMo_estimate = Eigen::Isometry3d::Identity();  ///< the object followed
  Eigen::Isometry3d dMe = Eigen::Isometry3d::Identity();  ///< the tool at the measured joints
  Eigen::Isometry3d bMg_target = Eigen::Isometry3d::Identity();  ///< the grasp target in b
  bool object_held_in_world = false;  ///< briefly lost: held at its last world pose
  double target_age_s = 0.0;          ///< since the target was last solved
  double pair_width_m = 0.0;          ///< the contact pair's width (0: not known)
};

class MissionEvaluator {
 public:
  /// `world`, `platform` and `collision` must outlive the evaluator; `log`
  /// writes one line at the present time.
  MissionEvaluator(const World& world, const Platform& platform, const PlatformCollision& collision,
                   ObjectSymmetry symmetry, std::function<void(const std::string&)> log);

  /// Each servo cycle: an arm whose true joints enter the safe volume counts,
  /// and so do the two arms coming into contact. A closing gripper's pads are
  /// logged against the true grasp once, when they hold or their opening
  /// reaches the pair's width (where the close is decided).
  void Step();
  /// A camera frame stamped stamp_s was taken now: the object's true pose then.
  void FrameTaken(double stamp_s);
  /// The frame's result: fills the sample's truth (object position, rotation
  /// error) and the joint targets the arms received; frames found while
  /// grasping (`counts`) add to the pose RMSE.
  void FramePerceived(double stamp_s, bool estimate_valid, const Eigen::Isometry3d& cMo_estimate,
                      bool counts, MissionSample* sample);
  /// Arm a (0 left, 1 right) starts to close: logs the tool against the grasp
  /// on the true object and keeps the grasp point (in o) the close aims at.
  void Closing(int a, const ClosingView& view);
  /// Arm a has closed: logs the tool on the true object and adds a close to
  /// closes() with the tool's error to the grasp point kept by Closing (0 when
  /// Closing was not called for this arm).
  void Closed(int a);

  bool both_hold() const;
  int safe_volume_entries() const { return safe_volume_entries_; }
  int arm_contacts() const { return arm_contacts_; }
  const std::vector<GripperClose>& closes() const { return closes_; }
  /// Frames that counted for the pose RMSE.
  int grasp_frames() const { return frames_; }
  /// < 0 when no frame counted.
  double pose_rmse_m() const;
  double rotation_rmse_deg() const;

 private:
  /// The grasp point Closing kept, on the true object, in arm a's true tool frame.
  Eigen::Vector3d TrueGraspInTool(int a) const;

  const World& world_;
  const Platform& platform_;
  const PlatformCollision& collision_;
  ObjectSymmetry symmetry_;
  std::function<void(const std::string&)> log_;
  std::map<double, Eigen::Isometry3d> dMo_at_frame_;  // frames taken and not yet perceived
  bool in_safe_volume_[2] = {false, false};
  int safe_volume_entries_ = 0;
  bool in_contact_ = false;
  int arm_contacts_ = 0;
  // Per arm, from Closing: the grasp point in o and the object's rotation as
  // the robot estimated it (the truth is compared in its nearest symmetric twin).
  bool closing_[2] = {false, false};
  Eigen::Vector3d closing_target_o_[2];
  Eigen::Matrix3d closing_dRo_estimate_[2];
  // While a gripper closes: its pair's width, whether the pads were logged at
  // it, and the true grasp point in the tool frame at the last cycle.
  double closing_width_m_[2] = {0.0, 0.0};
  bool closing_logged_[2] = {false, false};
  Eigen::Vector3d closing_e_p_[2];
  double closing_e_p_t_s_[2] = {0.0, 0.0};
  std::vector<GripperClose> closes_;
  double sq_position_ = 0.0, sq_rotation_ = 0.0;
  int frames_ = 0;
};

}  // namespace aerograsp
