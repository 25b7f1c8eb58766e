// Found / lost with hysteresis on the per-frame confidence: a track is found
// after `frames_to_find` consecutive frames at or above `find_confidence`, and
// lost after `frames_to_lose` consecutive frames below `keep_confidence`
// (keep < find, so a confidence wobbling between them changes nothing). A
// lost track is resumed sooner, after `frames_to_refind` frames, when its
// measurements continue it: the pose was tracked on from where the track last
// had it (no global search, no pose given from outside), so it is the same
// object where it was.
#pragma once

#include <string>

namespace aerograsp {

enum class TrackState { kLost, kFound };
const char* ToString(TrackState state);

struct TrackMonitorOptions {
  double find_confidence = 0.6;  ///< (keep_confidence, 1]
  double keep_confidence = 0.3;  ///< [0, find_confidence)
  int frames_to_find = 2;        ///< >= 1
  int frames_to_refind = 1;      ///< frames that continue a lost track, [1, frames_to_find]
  int frames_to_lose = 3;        ///< >= 1
  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

class TrackMonitor {
 public:
  explicit TrackMonitor(const TrackMonitorOptions& options = {});
  /// Feeds one frame's confidence, returns the state after it. `continues`:
  /// the frame's pose was tracked on from the track's last found pose.
  TrackState Update(double confidence, bool continues = false);
  TrackState state() const { return state_; }
  void Reset() {
    state_ = TrackState::kLost;
    good_ = bad_ = continuing_ = 0;
  }

 private:
  TrackMonitorOptions options_;
  TrackState state_ = TrackState::kLost;
  int good_ = 0, bad_ = 0, continuing_ = 0;
};

}  // namespace aerograsp
