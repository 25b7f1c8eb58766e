#include "hardware/autopilot.h"

namespace aerograsp {

const char* FlightModeName(FlightMode mode) {
  switch (mode) {
    case FlightMode::kDisarmed:
      return "disarmed";
    case FlightMode::kLanded:
      return "landed";
    case FlightMode::kTakingOff:
      return "taking-off";
    case FlightMode::kHold:
      return "hold";
    case FlightMode::kOffboard:
      return "offboard";
    case FlightMode::kLanding:
      return "landing";
  }
  return "unknown";
}

}  // namespace aerograsp
