// The two arms and their grippers as the algorithms see them: joint targets
// in, joint positions out, gripper open / close and state. Backends: the
// simulator and the Feetech servo bus.
#pragma once

#include <Eigen/Core>

#include "core/platform.h"

namespace aerograsp {

struct GripperState {
  double aperture_m = 0.0;  ///< current opening between the finger pads
  bool moving = false;      ///< still opening or closing
  bool closed = false;      ///< last command was close and the fingers stopped
  bool holding = false;     ///< closed on an object (fingers stopped before closing fully)
};

class ArmsDriver {
 public:
  virtual ~ArmsDriver() = default;
  /// Joint position targets (rad), one per joint; the driver clamps to limits.
  virtual void SetJointTargets(Side side, const Eigen::VectorXd& q_rad) = 0;
  /// Latest measured joint positions (rad).
  virtual Eigen::VectorXd JointPositions(Side side) const = 0;
  virtual void SetGripper(Side side, GripperCommand command) = 0;
  virtual GripperState Gripper(Side side) const = 0;
  /// Safe state: both arms hold their present positions.
  virtual void Stop() = 0;
};

}  // namespace aerograsp
