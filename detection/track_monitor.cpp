#include "detection/track_monitor.h"

#include "core/config.h"

namespace aerograsp {

const char* ToString(TrackState state) { return state == TrackState::kFound ? "found" : "lost"; }

void TrackMonitorOptions::Validate(const std::string& source, const std::string& prefix) const {
  auto fail = [&](const char* field, const char* what) {
    throw ConfigError(source + ": " + prefix + field + ": " + what);
  };
  if (!(find_confidence > keep_confidence && find_confidence <= 1.0)) {
    fail("find_confidence", "must be in (keep_confidence, 1]");
  }
  if (!(keep_confidence >= 0.0)) fail("keep_confidence", "must be >= 0");
  if (frames_to_find < 1) fail("frames_to_find", "must be >= 1");
  if (frames_to_lose < 1) fail("frames_to_lose", "must be >= 1");
  if (frames_to_refind < 1 || frames_to_refind > frames_to_find) {
    fail("frames_to_refind", "must be in [1, frames_to_find]");
  }
}

TrackMonitor::TrackMonitor(const TrackMonitorOptions& options) : options_(options) {
  options_.Validate("track options", "track.");
}

TrackState TrackMonitor::Update(double confidence, bool continues) {
  if (!(confidence == confidence)) confidence = 0.0;  // NaN counts as nothing
  if (state_ == TrackState::kLost) {
    const bool good = confidence >= options_.find_confidence;
    good_ = good ? good_ + 1 : 0;
    continuing_ = good && continues ? continuing_ + 1 : 0;
    if (good_ >= options_.frames_to_find || continuing_ >= options_.frames_to_refind) {
      state_ = TrackState::kFound;
      good_ = bad_ = continuing_ = 0;
    }
  } else {
    bad_ = confidence < options_.keep_confidence ? bad_ + 1 : 0;
    if (bad_ >= options_.frames_to_lose) {
      state_ = TrackState::kLost;
      good_ = bad_ = continuing_ = 0;
    }
  }
  return state_;
}

}  // namespace aerograsp
