#include <gtest/gtest.h>

#include <cstring>

#include "telemetry/cdr_writer.h"
#include "telemetry/ros_messages.h"

namespace aerograsp {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(CdrWriterTest, StartsWithTheLittleEndianEncapsulationHeader) {
  CdrWriter w;
  EXPECT_EQ(w.bytes(), (Bytes{0x00, 0x01, 0x00, 0x00}));
}

TEST(CdrWriterTest, StringIsLengthWithNulThenBytesThenNul) {
  CdrWriter w;
  w.String("hi");
  EXPECT_EQ(w.bytes(), (Bytes{0, 1, 0, 0, 3, 0, 0, 0, 'h', 'i', 0}));
}

TEST(CdrWriterTest, AlignsEachPrimitiveToItsSizeAfterTheHeader) {
  CdrWriter w;
  w.UInt8(0xAA);     // offset 0
  w.UInt16(0x0102);  // pad 1, offset 2
  w.UInt8(0xBB);     // offset 4
  w.Float64(1.0);    // pad 3, offset 8
  w.UInt8(0xCC);     // offset 16
  w.UInt32(7);       // pad 3, offset 20
  const Bytes body(w.bytes().begin() + 4, w.bytes().end());
  const Bytes want = {0xAA, 0,    0x02, 0x01, 0xBB, 0, 0, 0, 0x00, 0x00, 0x00, 0x00,
                      0x00, 0x00, 0xF0, 0x3F, 0xCC, 0, 0, 0, 7,    0,    0,    0};
  EXPECT_EQ(body, want);
}

TEST(CdrWriterTest, SequencesAreACountThenTheElements) {
  CdrWriter w;
  w.UInt8(1);
  w.Float64Sequence({2.5});
  const Bytes body(w.bytes().begin() + 4, w.bytes().end());
  // count at offset 4 (aligned), the double at offset 8.
  double v = 0;
  ASSERT_EQ(body.size(), 16u);
  EXPECT_EQ(body[4], 1);
  std::memcpy(&v, body.data() + 8, 8);
  EXPECT_EQ(v, 2.5);
}

TEST(RosMessagesTest, TimeSplitsIntoSecondsAndRoundedNanoseconds) {
  std::int32_t sec = -1;
  std::uint32_t nanosec = 0;
  RosTime(12.3456789014, &sec, &nanosec);
  EXPECT_EQ(sec, 12);
  EXPECT_EQ(nanosec, 345678901u);
  RosTime(0.9999999999, &sec, &nanosec);  // rounds up into the next second
  EXPECT_EQ(sec, 1);
  EXPECT_EQ(nanosec, 0u);
  RosTime(-3.0, &sec, &nanosec);
  EXPECT_EQ(sec, 0);
  EXPECT_EQ(nanosec, 0u);
}

TEST(RosMessagesTest, BoolMessageIsOneByte) { EXPECT_EQ(EncodeBool(true), (Bytes{0, 1, 0, 0, 1})); }

TEST(RosMessagesTest, LogLevelsAreRosOnes) {
  const Bytes log = EncodeLog(1.5, TelemetryLevel::kWarn, "n", "m");
  // sec 1, nanosec 5e8, then the level byte.
  ASSERT_GT(log.size(), 13u);
  EXPECT_EQ(log[4], 1);
  EXPECT_EQ(log[12], 30);
  EXPECT_EQ(EncodeLog(0, TelemetryLevel::kDebug, "", "")[12], 10);
  EXPECT_EQ(EncodeLog(0, TelemetryLevel::kFatal, "", "")[12], 50);
}

TEST(RosMessagesTest, DefinitionListsEachDependencyOnce) {
  const std::string text = Ros2MsgDefinition(ros_type::kPoseWithCovarianceStamped);
  EXPECT_EQ(text.rfind("std_msgs/Header header\nPoseWithCovariance pose\n", 0), 0u);
  for (const char* dep : {"MSG: std_msgs/Header\n", "MSG: builtin_interfaces/Time\n",
                          "MSG: geometry_msgs/Pose\n", "MSG: geometry_msgs/Quaternion\n"}) {
    const std::size_t at = text.find(dep);
    ASSERT_NE(at, std::string::npos) << dep;
    EXPECT_EQ(text.find(dep, at + 1), std::string::npos) << dep;
    EXPECT_EQ(text.substr(at - 81, 81), std::string(80, '=') + "\n");
  }
}

TEST(RosMessagesTest, UnknownTypeIsRefusedWithItsName) {
  try {
    Ros2MsgDefinition("nav_msgs/msg/Odometry");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nav_msgs/msg/Odometry"), std::string::npos);
  }
}

}  // namespace
}  // namespace aerograsp
