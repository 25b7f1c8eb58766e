// The object as the mission knows it, in one place: the tracker's estimate
// (filtered in the world), its last pose seen within the tracking radius, a
// low-passed world position the vehicle follows, its motion along its length
// fitted before an attempt (the fingers then hide its ends), and, while one
// gripper carries it, where it sits in that gripper. dMo() answers where the
// object is in the body frame now.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/runtime/mission_config.h"
#include "detection/model_cloud.h"
#include "detection/object_tracker.h"
#include "mission/object_motion.h"

namespace aerograsp {

class TrackedObject {
 public:
  /// `bounds_o`: the object's mesh bounds in o (its ends along x); `dMe(a)`:
  /// arm a's tool in the body frame at its measured joints; `log` writes one
  /// line at the present time.
  TrackedObject(const MissionConfig& config, ObjectSymmetry symmetry,
                const Eigen::AlignedBox3d& bounds_o, double frame_period_s,
                std::function<Eigen::Isometry3d(int)> dMe,
                std::function<void(const std::string&)> log);

  /// One frame's estimate, handled at t_s; dMc the camera in the body frame.
  void Update(double t_s, const ObjectEstimate& estimate, const Eigen::Isometry3d& dMc);
  /// Gripper a holds the object (the other re-aims): from now on it moves with
  /// that gripper, starting where the body-frame pose dMo puts it.
  void CarriedBy(int a, const Eigen::Isometry3d& dMo);
  /// Gripper a closed on nothing while the other carries the object: when it
  /// closed across the length near an end (EmptyCloseShiftM,
  /// empty_close_shift_max_m), the carried estimate moves along its length
  /// so that end lies at a's tool. True when it moved.
  bool ClosedOnNothing(int a);
  /// No gripper carries it any more (the attempt ended): frames fit its
  /// motion along its length again (LockLength).
  void Released();
  /// An attempt begins: until it ends or a gripper carries the object, its
  /// position along its length (x of o, the longest side) comes from its
  /// motion fitted over the last length_fit_s of frames that placed it along
  /// its length (ObjectEstimate::weak_direction_fixed; refitted on each new
  /// one, again from the newest when they say it stopped or turned:
  /// LengthMotion), not from each frame. False (nothing changes) when
  /// length_fit_s is 0 or too few frames saw it.
  bool LockLength();
  /// The fitted motion while locked, else none.
  const std::optional<AxisMotion>& length_motion() const { return length_.motion(); }

  /// The object in the body frame at t_s with the vehicle at wMd: in the
  /// holding gripper, at its last world pose moved on with its filtered
  /// velocity while briefly lost (HeldWorldDisplacement), else the estimate
  /// moved on with its velocity.
  Eigen::Isometry3d dMo(double t_s, const Eigen::Isometry3d& wMd) const;
  /// Briefly lost, held at its last world pose (GraspPolicyConfig::lost_timeout_s).
  bool HeldInWorld(double t_s) const;
  /// Seconds out of view at t_s; < 0 while in view.
  double lost_for_s(double t_s) const { return lost_since_s_ < 0 ? -1.0 : t_s - lost_since_s_; }

  bool found() const { return found_; }
  const ObjectEstimate& estimate() const { return estimate_; }
  double last_found_stamp_s() const { return last_found_stamp_s_; }
  int holder() const { return holder_; }
  /// Seen within the tracking radius at least once; then its filtered world position.
  bool have_world_pose() const { return have_wMo_; }
  const Eigen::Vector3d& object_w_filtered() const { return object_w_filtered_; }

 private:
  static LengthFitOptions LengthOptions(const MissionConfig& config, double frame_period_s);
  /// How far the held pose has moved on from the last world pose at t_s.
  Eigen::Vector3d HeldDisplacement(double t_s) const;

  const MissionConfig& config_;
  ObjectSymmetry symmetry_;
  Eigen::AlignedBox3d bounds_o_;
  double alpha_;  // low-pass gain per frame
  std::function<Eigen::Isometry3d(int)> dMe_;
  std::function<void(const std::string&)> log_;
  ObjectEstimate estimate_;
  bool found_ = false;
  double lost_since_s_ = -1.0;
  double last_found_stamp_s_ = 0.0;
  bool have_wMo_ = false;
  Eigen::Isometry3d wMo_last_ = Eigen::Isometry3d::Identity();  // at the last found frame
  Eigen::Vector3d object_w_filtered_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d object_v_w_filtered_ = Eigen::Vector3d::Zero();  // low-passed as the position
  bool logged_beyond_ = false;
  int holder_ = -1;
  Eigen::Isometry3d eMo_held_ = Eigen::Isometry3d::Identity();  // in the holding gripper
  LengthMotion length_;  // fitted on the frames that place the object along its length
};

}  // namespace aerograsp
