#include "app/runtime/mission_object.h"

#include <fmt/format.h>

#include <algorithm>

#include "app/runtime/mission_vehicle.h"
#include "core/symmetry.h"

namespace aerograsp {

TrackedObject::TrackedObject(const MissionConfig& config, ObjectSymmetry symmetry,
                             const Eigen::AlignedBox3d& bounds_o, double frame_period_s,
                             std::function<Eigen::Isometry3d(int)> dMe,
                             std::function<void(const std::string&)> log)
    : config_(config),
      symmetry_(std::move(symmetry)),
      bounds_o_(bounds_o),
      alpha_(std::min(1.0, frame_period_s / config.object_filter_s)),
      dMe_(std::move(dMe)),
      log_(std::move(log)),
      length_(LengthOptions(config, frame_period_s)) {}

void TrackedObject::Update(double t, const ObjectEstimate& estimate, const Eigen::Isometry3d& dMc) {
  estimate_ = estimate;
  found_ = estimate_.valid && estimate_.state == TrackState::kFound;
  // The frames that placed the object along its length too fit its motion.
  const Eigen::Vector3d measured_w = estimate_.fMo.translation();
  if (found_ && estimate_.weak_direction_fixed && holder_ < 0 && config_.length_fit_s > 0.0 &&
      !BeyondTrackingRadius(measured_w, config_)) {
    if (length_.Add({estimate_.stamp_s, measured_w})) {
      log_(fmt::format(
          "vision: {} frames in a row place the object over {:.0f} mm off its fitted motion "
          "along its length: it stopped or turned; fitted again from them",
          config_.length_break_frames, 1e3 * config_.length_break_m));
    }
  }
  const std::optional<AxisMotion>& length = length_.motion();
  if (length && estimate_.valid && holder_ < 0) {
    // Along its length the object is where its fitted motion puts it (not
    // once a gripper carries it: then it moves with that gripper).
    const Eigen::Vector3d& u = length->axis_w;
    const Eigen::Vector3d p_w = estimate_.fMo.translation();
    const Eigen::Isometry3d fMo_before = estimate_.fMo;
    estimate_.fMo.translation() = length->Constrain(p_w, estimate_.stamp_s);
    estimate_.cMo = estimate_.cMo * fMo_before.inverse() * estimate_.fMo;
    estimate_.v_f += (length->v_mps - u.dot(estimate_.v_f)) * u;
  }
  if (found_) {
    lost_since_s_ = -1.0;
    last_found_stamp_s_ = estimate_.stamp_s;
  } else if (lost_since_s_ < 0) {
    lost_since_s_ = t;
  }
  const Eigen::Vector3d object_w = estimate_.fMo.translation();
  const bool beyond = BeyondTrackingRadius(object_w, config_);
  if (found_ && beyond && !logged_beyond_) {
    logged_beyond_ = true;
    log_(fmt::format(
        "vision: the object is seen {:.2f} m from the approach waypoint, beyond the tracking "
        "radius: not followed",
        (object_w - config_.approach_w_m).norm()));
  }
  if (found_ && holder_ >= 0) {
    // Held by one gripper the object moves with it: each frame's estimate
    // refines where it sits in that gripper (it was taken from the estimate
    // when the gripper closed, often while the fingers hid the object).
    const Eigen::Isometry3d dMo_estimate = dMc * estimate_.cMo;  // at the frame
    Eigen::Isometry3d eMo = dMe_(holder_).inverse() * dMo_estimate;
    // Its symmetric twin nearest the held pose, turned about the symmetry's centre.
    eMo = WithSymmetricRotation(
        eMo, ClosestSymmetricRotation(eMo.linear(), eMo_held_.linear(), symmetry_), symmetry_);
    // Along its length only from a frame that saw it (the fingers hide its ends).
    Eigen::Vector3d step_e = eMo.translation() - eMo_held_.translation();
    if (!estimate_.weak_direction_fixed) {
      const Eigen::Vector3d x_e = eMo_held_.linear().col(0);
      step_e -= x_e.dot(step_e) * x_e;
    }
    eMo_held_.translation() += alpha_ * step_e;
    eMo_held_.linear() = Eigen::Quaterniond(eMo_held_.linear())
                             .slerp(alpha_, Eigen::Quaterniond(eMo.linear()))
                             .normalized()
                             .toRotationMatrix();
  }
  if (found_ && !beyond) {
    logged_beyond_ = false;
    object_w_filtered_ =
        have_wMo_ ? object_w_filtered_ + alpha_ * (object_w - object_w_filtered_) : object_w;
    object_v_w_filtered_ =
        have_wMo_ ? object_v_w_filtered_ + alpha_ * (estimate_.v_f - object_v_w_filtered_)
                  : estimate_.v_f;
    wMo_last_ = estimate_.fMo;
    have_wMo_ = true;
  }
}

LengthFitOptions TrackedObject::LengthOptions(const MissionConfig& config, double frame_period_s) {
  LengthFitOptions o;
  o.window_s = config.length_fit_s;
  // Half the window's frames at the camera's rate.
  o.lock_min_frames = std::max(2, static_cast<int>(0.5 * config.length_fit_s / frame_period_s));
  o.refit_min_frames = config.length_refit_frames;
  o.break_m = config.length_break_m;
  o.break_frames = config.length_break_frames;
  return o;
}

bool TrackedObject::LockLength() {
  if (config_.length_fit_s <= 0.0 || !estimate_.valid) return false;
  if (!length_.Lock(estimate_.fMo.linear().col(0))) return false;
  log_(
      fmt::format("vision: along its length the object moves {:+.1f} mm/s (fitted over {} "
                  "frames); that fit, refitted on each frame that sees the object whole, places "
                  "it along its length until the attempt ends",
                  1e3 * length_.motion()->v_mps, length_.frames()));
  return true;
}

void TrackedObject::Released() {
  holder_ = -1;
  length_.Reset();
}

void TrackedObject::CarriedBy(int a, const Eigen::Isometry3d& dMo) {
  if (holder_ < 0) eMo_held_ = dMe_(a).inverse() * dMo;
  holder_ = a;
}

bool TrackedObject::ClosedOnNothing(int a) {
  if (holder_ < 0 || a == holder_) return false;
  const Eigen::Isometry3d oMe = eMo_held_.inverse() * dMe_(holder_).inverse() * dMe_(a);
  // Closing across the length (the tool's x axis, its closing direction,
  // within 60 deg of square to x of o): along the length the pads' position
  // decides whether they meet the object.
  if (std::abs(oMe.linear().col(0).x()) > 0.5) return false;
  const double shift_m = EmptyCloseShiftM(oMe.translation().x(), bounds_o_.min().x(),
                                          bounds_o_.max().x(), config_.empty_close_shift_max_m);
  if (shift_m == 0.0) return false;
  eMo_held_ = eMo_held_ * Eigen::Translation3d(shift_m, 0.0, 0.0);
  log_(fmt::format(
      "vision: the {} gripper closed on nothing {:.0f} mm inside the carried object's end: the "
      "object's estimate moves as far along its length, that end to the tool",
      kArmNames[a], 1e3 * std::abs(shift_m)));
  return true;
}

bool TrackedObject::HeldInWorld(double t) const {
  return HoldLastWorldPose(have_wMo_, found_, lost_for_s(t), config_.policy);
}

Eigen::Vector3d TrackedObject::HeldDisplacement(double t) const {
  return HeldWorldDisplacement(object_v_w_filtered_, t - last_found_stamp_s_, config_.policy);
}

Eigen::Isometry3d TrackedObject::dMo(double t, const Eigen::Isometry3d& wMd) const {
  // Held by one gripper: the object goes where that gripper goes.
  if (holder_ >= 0) return dMe_(holder_) * eMo_held_;
  // Briefly lost (the grippers hide the object as they close in): the object
  // is held where it was last seen in the world, moved on as far as its
  // filtered velocity is trusted, and the vehicle's own pose carries it into
  // the body frame through the sway.
  const Eigen::Isometry3d dMw = wMd.inverse();
  if (HeldInWorld(t)) {
    Eigen::Isometry3d wMo = wMo_last_;
    wMo.translation() += HeldDisplacement(t);
    if (const auto& length = length_.motion())
      wMo.translation() = length->Constrain(wMo.translation(), t);
    return dMw * wMo;
  }
  // The filter runs in the world (the object crawls slowly there, while the
  // camera sways): the vehicle's pose now brings it into the body, moved on
  // with its velocity.
  Eigen::Isometry3d wMo = estimate_.fMo;
  wMo.translation() +=
      estimate_.v_f * std::clamp(t - estimate_.stamp_s, 0.0, config_.predict_max_s);
  return dMw * wMo;
}

}  // namespace aerograsp
