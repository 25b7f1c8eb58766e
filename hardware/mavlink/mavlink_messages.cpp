#include "hardware/mavlink/mavlink_messages.h"

#include <algorithm>

namespace aerograsp {
namespace mavlink {

const char* MavResultName(std::uint8_t result) {
  switch (result) {
    case kResultAccepted:
      return "accepted";
    case kResultTemporarilyRejected:
      return "temporarily rejected";
    case kResultDenied:
      return "denied";
    case kResultUnsupported:
      return "unsupported";
    case kResultFailed:
      return "failed";
    case kResultInProgress:
      return "in progress";
    case kResultCancelled:
      return "cancelled";
    default:
      return "unknown result";
  }
}

void StatusText::SetText(const std::string& s) {
  text.fill('\0');
  std::copy_n(s.begin(), std::min(s.size(), text.size()), text.begin());
}

std::string StatusText::Text() const {
  const auto end = std::find(text.begin(), text.end(), '\0');
  return std::string(text.begin(), end);
}

}  // namespace mavlink
}  // namespace aerograsp
