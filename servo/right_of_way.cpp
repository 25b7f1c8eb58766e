#include "servo/right_of_way.h"

#include <cassert>

namespace aerograsp {

void RightOfWay::Post(int seat, double now_s, bool held, double to_target_m) {
  assert(seat == 0 || seat == 1);
  posts_[seat] = {held, to_target_m, now_s};
}

bool RightOfWay::ShouldYield(int seat, double now_s, double to_target_m, double fresh_s) const {
  assert(seat == 0 || seat == 1);
  const Entry& other = posts_[1 - seat];
  if (!other.held || !(now_s - other.stamp_s <= fresh_s)) return false;
  return to_target_m > other.to_target_m || (to_target_m == other.to_target_m && seat == 1);
}

}  // namespace aerograsp
