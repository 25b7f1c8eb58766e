// Right of way between the two arms' servos. Each arm searches a joint path to
// its target that the other arm's current joints allow (servo/arm_servo.h);
// when both arms move at once their paths can cross, and each then holds
// because the other stands in its way, for good. The two servos share a
// RightOfWay: each posts every cycle whether it is held and how far it is from
// its target, and when both are held the one farther from its target makes way
// (it backs off to a via configuration and searches again from there) while
// the nearer one goes first.
#pragma once

#include <cmath>

namespace aerograsp {

/// Shared by the servos of the two arms, seats 0 and 1; the caller owns it and
/// it must outlive both servos. Not thread-safe: step both servos in one thread.
class RightOfWay {
 public:
  /// Arm `seat` (0 or 1) at time now_s (s): whether it is held with no allowed
  /// path or step toward its target, and its distance to the target (m).
  void Post(int seat, double now_s, bool held, double to_target_m);

  /// True when the arm in `seat`, held at now_s at to_target_m (m) from its
  /// target, should make way: the other arm posted within fresh_s (s) that it
  /// is held too, and is nearer its target (on a tie seat 1 makes way).
  bool ShouldYield(int seat, double now_s, double to_target_m, double fresh_s) const;

 private:
  struct Entry {
    bool held = false;
    double to_target_m = 0.0;
    double stamp_s = -INFINITY;
  };
  Entry posts_[2];
};

}  // namespace aerograsp
