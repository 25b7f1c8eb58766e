#include "servo/collision_predicate.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace aerograsp {

ForbiddenPredicate MakeCollisionPredicate(const PlatformCollision& collision, Side side,
                                          double margin_m, const Eigen::VectorXd* q_other) {
  if (!(margin_m >= 0.0) || !std::isfinite(margin_m)) {
    throw std::invalid_argument("collision predicate: margin_m " + std::to_string(margin_m) +
                                " m must be finite and >= 0");
  }
  return [&collision, side, margin_m, q_other](const Eigen::VectorXd& q) {
    try {
      if (collision.ArmInSafeVolume(side, q, margin_m)) return true;
      if (!q_other) return false;
      return side == Side::kLeft ? collision.ArmsCollide(q, *q_other, margin_m)
                                 : collision.ArmsCollide(*q_other, q, margin_m);
    } catch (const std::invalid_argument&) {
      return true;  // a joint vector of the wrong size: unknown counts as forbidden
    }
  };
}

}  // namespace aerograsp
