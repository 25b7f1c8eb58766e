// One arm's servo loop: PBVS twist (servo/pbvs.h) -> prioritized damped least
// squares (position first, then orientation) -> joint-limit avoidance, speed
// and acceleration limits -> safe-volume check -> joint targets. Bad input never
// throws out of Step(): it returns a hold status with a zero velocity.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <string>

#include "core/arm_model.h"
#include "servo/dls.h"
#include "servo/pbvs.h"

namespace aerograsp {

struct ServoConfig {
  double gain_per_s{3.0};              ///< PBVS error decrease rate lambda, (0, 50] 1/s
  double switch_blend_per_s{10.0};     ///< rate at which a target switch blends in, (0, 100] 1/s
  DampingOptions damping{};            ///< singular_threshold, max_damping: (0, 1]
  double speed_fraction{0.8};          ///< of each joint's URDF velocity limit, (0, 1]
  double max_accel_rad_s2{30.0};       ///< per joint, smoothing, (0, 1000] rad/s^2
  double limit_zone_rad{0.15};         ///< joint-limit avoidance acts this close to a limit, [0, 1] rad
  double limit_gain_per_s{2.0};        ///< strength of the avoidance, [0, 100] 1/s
  /// Weights of the orientation error about the tool's x, y, z axes, [0, 1]
  /// each. The 4-DoF arm cannot reach every orientation: position always comes
  /// first, orientation is met within what position leaves free.
  Eigen::Vector3d orientation_weights{1.0, 1.0, 1.0};
  double stale_target_s{0.2};          ///< a target older than this is refused, (0, 10] s

  /// @throws ConfigError "<source>: servo.<field>: ..." for out-of-range values.
  void Validate(const std::string& source) const;
};

enum class ServoStatus {
  kMoving,           ///< a velocity toward the target was commanded
  kNoTarget,         ///< holding: no target set yet
  kStaleTarget,      ///< holding: the target is older than stale_target_s
  kInvalidTarget,    ///< holding: the target has NaN/Inf or is not a rigid transform
  kInvalidState,     ///< holding: q has NaN/Inf or the wrong size
  kSafeVolume,       ///< holding: every scaled step would enter the forbidden region
};
const char* ServoStatusName(ServoStatus status);

struct ServoCommand {
  Eigen::VectorXd dq_rad_s;       ///< commanded joint velocities
  Eigen::VectorXd q_target_rad;   ///< q + dq * dt: the joint targets to send
  double position_error_m = 0.0;  ///< |p_g - p_e|
  double rotation_error_rad = 0.0;
  double damping = 0.0;           ///< lambda of the primary task
  double min_singular = 0.0;      ///< smallest singular value of the position Jacobian
  double step_scale = 1.0;        ///< < 1 when speed or safe-volume limits shortened the step
};

/// True when the arm at joint positions q must not be commanded (e.g. it would
/// be inside the vehicle's safe volume). Supplied by the app (core/collision.h).
using ForbiddenPredicate = std::function<bool(const Eigen::VectorXd& q)>;

class ArmServo {
 public:
  /// `arm` must outlive the servo. @throws ConfigError when config is invalid.
  ArmServo(const ArmModel& arm, const ServoConfig& config, ForbiddenPredicate forbidden = {});

  /// Forget motion history: the next command starts from rest.
  void Reset();
  /// A new target bMg (the grasp or pre-grasp in the arm base) observed at stamp_s.
  /// When the target changes to another grasp pass `is_switch`: the commanded
  /// velocity then stays continuous (the old command fades at switch_blend_per_s).
  void SetTarget(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch = false);

  /// One cycle at time now_s with measured joints q and period dt_s (> 0).
  /// Never throws; on any hold status dq is zero and q_target is q (or the last
  /// good q when q itself is invalid).
  ServoStatus Step(const Eigen::VectorXd& q, double now_s, double dt_s, ServoCommand* out);

 private:
  ServoStatus Hold(const Eigen::VectorXd& q, ServoStatus status, ServoCommand* out);

  const ArmModel& arm_;
  ServoConfig config_;
  ForbiddenPredicate forbidden_;
  PbvsTask pbvs_;
  bool has_target_ = false;
  Eigen::Isometry3d bMg_ = Eigen::Isometry3d::Identity();
  double target_stamp_s_ = 0.0;
  Eigen::VectorXd last_dq_;       // previous command (for smoothing and blending)
  Eigen::VectorXd switch_dq_;     // command at the last switch, fading out
  bool switch_pending_ = false;   // a switch was declared; the blend starts at the next Step
  double switch_time_s_ = -1.0;   // < 0: no blend active
  Eigen::VectorXd last_good_q_;
};

}  // namespace aerograsp
