#include <gtest/gtest.h>

#include <cmath>

#include "core/config.h"
#include "detection/track_monitor.h"

namespace aerograsp {
namespace {

TEST(TrackMonitorTest, FoundNeedsConsecutiveGoodFrames) {
  TrackMonitor m;  // find at 0.6 for 2 frames, lose below 0.3 for 3 frames
  EXPECT_EQ(m.Update(0.9), TrackState::kLost);
  EXPECT_EQ(m.Update(0.5), TrackState::kLost);  // resets the count
  EXPECT_EQ(m.Update(0.9), TrackState::kLost);
  EXPECT_EQ(m.Update(0.9), TrackState::kFound);
}

TEST(TrackMonitorTest, HysteresisKeepsATrackThroughWobbles) {
  TrackMonitor m;
  m.Update(1.0);
  m.Update(1.0);
  ASSERT_EQ(m.state(), TrackState::kFound);
  for (int i = 0; i < 10; ++i)
    EXPECT_EQ(m.Update(i % 2 ? 0.35 : 0.1), TrackState::kFound);  // never 3 bad in a row
  EXPECT_EQ(m.Update(0.2), TrackState::kFound);
  EXPECT_EQ(m.Update(0.0), TrackState::kFound);
  EXPECT_EQ(m.Update(0.29), TrackState::kLost);
  // Between the thresholds does not find it again.
  for (int i = 0; i < 5; ++i) EXPECT_EQ(m.Update(0.5), TrackState::kLost);
}

TEST(TrackMonitorTest, ALostTrackThatContinuesIsFoundAgainSooner) {
  TrackMonitor m;  // frames_to_refind 1
  m.Update(1.0);
  m.Update(1.0);
  for (int i = 0; i < 3; ++i) m.Update(0.0);
  ASSERT_EQ(m.state(), TrackState::kLost);
  EXPECT_EQ(m.Update(0.5, true), TrackState::kLost);  // too weak, continuing or not
  EXPECT_EQ(m.Update(0.9, true), TrackState::kFound);
  for (int i = 0; i < 3; ++i) m.Update(0.0);
  ASSERT_EQ(m.state(), TrackState::kLost);
  EXPECT_EQ(m.Update(0.9, false), TrackState::kLost);  // a fresh search still needs frames_to_find
  EXPECT_EQ(m.Update(0.9, false), TrackState::kFound);
  TrackMonitorOptions o;
  o.frames_to_refind = 3;
  o.frames_to_find = 3;
  TrackMonitor slow(o);
  EXPECT_EQ(slow.Update(0.9, true), TrackState::kLost);
  EXPECT_EQ(slow.Update(0.9, true), TrackState::kLost);
  EXPECT_EQ(slow.Update(0.9, true), TrackState::kFound);
}

TEST(TrackMonitorTest, NanCountsAsNothing) {
  TrackMonitor m;
  m.Update(1.0);
  m.Update(1.0);
  for (int i = 0; i < 3; ++i) m.Update(std::nan(""));
  EXPECT_EQ(m.state(), TrackState::kLost);
}

TEST(TrackMonitorTest, BadOptionsAreRejectedByName) {
  TrackMonitorOptions o;
  o.keep_confidence = 0.7;
  EXPECT_THROW({ TrackMonitor m(o); }, ConfigError);
  o = {};
  o.frames_to_lose = 0;
  try {
    o.Validate("track.yaml", "track.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "track.yaml: track.frames_to_lose: must be >= 1");
  }
  o = {};
  o.frames_to_refind = 3;  // more than frames_to_find
  try {
    o.Validate("track.yaml", "track.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "track.yaml: track.frames_to_refind: must be in [1, frames_to_find]");
  }
}

}  // namespace
}  // namespace aerograsp
