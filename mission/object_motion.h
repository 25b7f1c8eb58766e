// The object's motion along its length, fitted from the frames that saw it
// whole. Once the arms move in, their fingers hide the object's ends and a
// frame no longer says where it lies along its length (the slide of an
// extrusion along itself fits its visible middle equally well); its motion
// fitted before, s(t) = s0 + v (t - t0) along a fixed world axis, does.
// Pure functions of explicit inputs.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace aerograsp {

/// One frame's object position in the world.
struct StampedPosition {
  double stamp_s = 0.0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};

/// s(t) = s0_m + v_mps (t - t0_s): the position along axis_w (a unit vector).
struct AxisMotion {
  Eigen::Vector3d axis_w = Eigen::Vector3d::UnitX();
  double t0_s = 0.0;
  double s0_m = 0.0;
  double v_mps = 0.0;

  double At(double t_s) const { return s0_m + v_mps * (t_s - t0_s); }
  /// p_w with its component along the axis replaced by the fit's at t_s.
  Eigen::Vector3d Constrain(const Eigen::Vector3d& p_w, double t_s) const;
};

/// The least-squares line through the positions along axis_w (normalised
/// here) against time, t0_s the latest stamp; none with fewer than
/// min_samples positions or all at one time.
std::optional<AxisMotion> FitAxisMotion(const std::vector<StampedPosition>& positions,
                                        const Eigen::Vector3d& axis_w, int min_samples);

}  // namespace aerograsp
