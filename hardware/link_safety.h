// What the mission does when the autopilot link is lost: both arms
// hold where they are, so nothing swings while the vehicle runs its own
// failsafe. The mission calls this every cycle with the latest vehicle state.
#pragma once

#include "hardware/arms_driver.h"
#include "hardware/autopilot.h"

namespace aerograsp {

/// Stops both arms (ArmsDriver::Stop) when `vehicle.link_ok` is false.
/// Returns true when it stopped them.
inline bool HoldArmsOnLinkLoss(const VehicleState& vehicle, ArmsDriver* arms) {
  if (vehicle.link_ok) return false;
  arms->Stop();
  return true;
}

}  // namespace aerograsp
