#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "core/config.h"
#include "telemetry/telemetry.h"
#include "telemetry/telemetry_config.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {

/// Counts the calls it gets, appending its tag to a shared order.
class CountingSink final : public TelemetrySink {
 public:
  CountingSink(char tag, std::string* order) : tag_(tag), order_(order) {}
  void StaticTransforms(double, const std::vector<TelemetryTransform>&) override { Hit(); }
  void Transforms(double, const std::vector<TelemetryTransform>&) override { Hit(); }
  void ObjectPose(const TelemetryObjectPose&) override { Hit(); }
  void Arms(const TelemetryArms&) override { Hit(); }
  void Transition(const TelemetryTransition&) override { Hit(); }
  void GraspPair(const TelemetryGraspPair&) override { Hit(); }
  void Image(const TelemetryImage&) override { Hit(); }
  void Log(double, TelemetryLevel, const std::string&, const std::string&) override { Hit(); }
  void Close() override { Hit(); }

 private:
  void Hit() { *order_ += tag_; }
  char tag_;
  std::string* order_;
};

TEST(FanOutSinkTest, HandsEveryCallToEachSinkInOrder) {
  std::string order;
  FanOutSink fan;
  EXPECT_TRUE(fan.empty());
  fan.Add(std::make_unique<CountingSink>('a', &order));
  fan.Add(std::make_unique<CountingSink>('b', &order));
  fan.Add(nullptr);  // ignored
  EXPECT_FALSE(fan.empty());
  fan.StaticTransforms(0.0, {});
  fan.Transforms(0.0, {});
  fan.ObjectPose({});
  fan.Arms({});
  fan.Transition({});
  fan.GraspPair({});
  fan.Image({});
  fan.Log(0.0, TelemetryLevel::kInfo, "test", "line");
  fan.Close();
  EXPECT_EQ(order, "ababababababababab");
}

TEST(MapMWorldTest, TurnsNedIntoEnu) {
  const Eigen::Isometry3d mapMw = MapMWorld();
  // North, east, down in w are y, x, -z in map.
  EXPECT_TRUE((mapMw * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_TRUE((mapMw * Eigen::Vector3d(0, 1, 0)).isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE((mapMw * Eigen::Vector3d(0, 0, 1)).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_NEAR(mapMw.linear().determinant(), 1.0, 1e-12);
}

TEST(EmergencyStopLatchTest, QuietUntilRequested) {
  EmergencyStopLatch latch;
  const EmergencyStopPoll poll = latch.Poll(0.0);
  EXPECT_FALSE(poll.stop);
  EXPECT_TRUE(poll.notes.empty());
}

TEST(EmergencyStopLatchTest, KeepsTheFirstRequestFromAnotherThread) {
  EmergencyStopLatch latch;
  std::thread listener([&] {
    latch.Note("listener: a malformed message was ignored");
    latch.Request("ros2 /emergency_stop", "true received");
    latch.Request("second", "ignored");
  });
  listener.join();
  const EmergencyStopPoll poll = latch.Poll(1.0);
  EXPECT_TRUE(poll.stop);
  EXPECT_EQ(poll.source, "ros2 /emergency_stop");
  EXPECT_EQ(poll.reason, "true received");
  ASSERT_EQ(poll.notes.size(), 1u);
  // Notes are said once; the stop stays requested.
  const EmergencyStopPoll again = latch.Poll(1.01);
  EXPECT_TRUE(again.stop);
  EXPECT_TRUE(again.notes.empty());
}

TEST(TelemetryConfigTest, ShippedFileEqualsTheDefaults) {
  const TelemetryConfig shipped =
      TelemetryConfig::Load(std::string(AEROGRASP_DATA_DIR) + "/config/telemetry.yaml");
  const McapConfig defaults;
  EXPECT_EQ(shipped.mcap.enabled, defaults.enabled);
  EXPECT_EQ(shipped.mcap.image_rate_hz, defaults.image_rate_hz);
  EXPECT_EQ(shipped.mcap.jpeg_quality, defaults.jpeg_quality);
  EXPECT_EQ(shipped.mcap.depth, defaults.depth);
  EXPECT_EQ(shipped.mcap.state_rate_hz, defaults.state_rate_hz);
  EXPECT_EQ(shipped.mcap.compression, defaults.compression);
  EXPECT_EQ(shipped.mcap.chunk_size_kib, defaults.chunk_size_kib);
}

std::string LoadError(const std::string& yaml) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "aerograsp_telemetry_config.yaml").string();
  std::ofstream(path) << yaml;
  try {
    TelemetryConfig::Load(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(TelemetryConfigTest, BadValuesAreNamedWithTheirBound) {
  EXPECT_THAT(LoadError("mcap:\n  jpeg_quality: 5\n"),
              ::testing::HasSubstr("mcap.jpeg_quality: 5 is below the lower bound 10"));
  EXPECT_THAT(LoadError("mcap:\n  compression: gzip\n"), ::testing::HasSubstr("mcap.compression"));
  EXPECT_THAT(LoadError("mcap:\n  image_rate_hz: 0\n"), ::testing::HasSubstr("image_rate_hz"));
  EXPECT_THAT(LoadError("mcap:\n  imge_rate_hz: 2\n"), ::testing::HasSubstr("imge_rate_hz"));
}

TEST(TelemetryConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  TelemetryConfig c;
  c.mcap.jpeg_quality = 5;
  EXPECT_THAT(testing::ValidationMessage(c, "t.yaml", ""),
              ::testing::HasSubstr("t.yaml: mcap.jpeg_quality: 5 is below the lower bound 10"));
  EXPECT_THAT(
      testing::ValidationMessage(c, "t.yaml", "telemetry."),
      ::testing::HasSubstr("t.yaml: telemetry.mcap.jpeg_quality: 5 is below the lower bound 10"));
  c = TelemetryConfig{};
  c.ros2.topic_namespace = "/robot";
  EXPECT_THAT(testing::ValidationMessage(c, "t.yaml", "telemetry."),
              ::testing::HasSubstr("t.yaml: telemetry.ros2.topic_namespace: '/robot' must not"));
}

}  // namespace
}  // namespace aerograsp
