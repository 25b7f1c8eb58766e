// The object's motion along its length, fitted from the frames that saw it
// whole. Once the arms move in, their fingers hide the object's ends and a
// frame no longer says where it lies along its length (the slide of an
// extrusion along itself fits its visible middle equally well); its motion
// fitted before, s(t) = s0 + v (t - t0) along a fixed world axis, does.
// Pure functions of explicit inputs.
#pragma once

#include <Eigen/Core>
#include <cstddef>
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

/// What a gripper that closed on nothing says about the object's position
/// along its length: its pads closed across the length at x_tool_m along x
/// of the object's estimate, whose ends lie at x_min_m and x_max_m, so the
/// object's nearer end lay short of the tool. The shift along x of o (m) that
/// puts that end at the tool: x_tool_m - x_max_m (<= 0) or x_tool_m - x_min_m
/// (>= 0). 0 when the tool lies outside the ends, or more than max_shift_m
/// inside them (a position error along the length does not explain the miss).
double EmptyCloseShiftM(double x_tool_m, double x_min_m, double x_max_m, double max_shift_m);

/// How the motion along the length is fitted and followed.
struct LengthFitOptions {
  double window_s = 3.0;     ///< frames older than this before the newest are dropped
  int lock_min_frames = 2;   ///< frames a fit needs when the attempt begins (Lock)
  int refit_min_frames = 2;  ///< frames a refit needs once locked
  /// A frame this far along the axis from the fit disagrees with it, m.
  double break_m = 0.02;
  /// This many disagreeing frames in a row say the motion changed (the
  /// object stopped or turned): the fit starts again from them.
  int break_frames = 3;
};

/// The object's motion along its length, followed over the frames that place
/// it along its length. Before Lock the frames of the last window_s are kept;
/// once locked each new frame refits the motion, unless it disagrees with it
/// (break_m): break_frames such frames in a row start a new fit from them
/// alone, standing still where they put the object until refit_min_frames
/// of them give a speed. A single disagreeing frame is set aside.
class LengthMotion {
 public:
  explicit LengthMotion(const LengthFitOptions& options) : options_(options) {}

  /// A frame that placed the object along its length. True when it began a
  /// new fit (the motion changed).
  bool Add(const StampedPosition& frame);
  /// The attempt begins: fits along axis_w; false (not locked) with too few frames.
  bool Lock(const Eigen::Vector3d& axis_w);
  /// The attempt ended: frames are gathered afresh.
  void Reset();

  /// The fitted motion while locked, else none.
  const std::optional<AxisMotion>& motion() const { return motion_; }
  std::size_t frames() const { return frames_.size(); }
  /// Times the motion changed (a new fit began) since the lock.
  int breaks() const { return breaks_; }

 private:
  void DropOlderThan(double stamp_s);
  void Refit();

  LengthFitOptions options_;
  std::vector<StampedPosition> frames_;
  std::vector<StampedPosition> disagreeing_;  // in a row, set aside
  std::optional<AxisMotion> motion_;
  int breaks_ = 0;
};

}  // namespace aerograsp
