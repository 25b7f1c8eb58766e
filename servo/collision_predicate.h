// The servo's forbidden predicate from the platform's collision model
// (core/collision.h): the safe volume above the shoulders and, optionally, the
// other arm.
#pragma once

#include <Eigen/Core>

#include "core/collision.h"
#include "servo/arm_servo.h"

namespace aerograsp {

/// A ForbiddenPredicate for the arm on `side`: true when the arm at q is within
/// margin_m (m, >= 0) of the safe volume, or, when q_other is not null, within
/// margin_m of the other arm at *q_other (read at each call, so the caller keeps
/// it at the other arm's latest joints). A q or *q_other with NaN or of the
/// wrong size counts as forbidden (never throws).
/// `collision` (and *q_other) must outlive the predicate.
/// @throws std::invalid_argument when margin_m is negative or not finite.
ForbiddenPredicate MakeCollisionPredicate(const PlatformCollision& collision, Side side,
                                          double margin_m,
                                          const Eigen::VectorXd* q_other = nullptr);

}  // namespace aerograsp
