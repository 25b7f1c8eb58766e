#include <gtest/gtest.h>

#include <cmath>

#include "hardware/scs/scs_protocol.h"
#include "hardware/scs/servo_calibration.h"

namespace aerograsp {
namespace {

std::vector<scs::PacketParser::Result> Feed(scs::PacketParser* parser,
                                            const std::vector<std::uint8_t>& bytes) {
  std::vector<scs::PacketParser::Result> out;
  for (std::uint8_t b : bytes) {
    const auto r = parser->Push(b);
    if (r != scs::PacketParser::Result::kNeedMore) out.push_back(r);
  }
  return out;
}

TEST(ScsProtocolTest, PingOfServoOneIsTheDocumentedPacket) {
  // ~(0x01 + 0x02 + 0x01) & 0xFF = 0xFB
  EXPECT_EQ(scs::EncodePing(1), (std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB}));
}

TEST(ScsProtocolTest, ReadAndWriteCarryAddressLengthAndBigEndianData) {
  const auto read = scs::EncodeRead(12, scs::reg::kPresentPosition, 2);
  EXPECT_EQ(read, (std::vector<std::uint8_t>{0xFF, 0xFF, 12, 4, 0x02, 56, 2,
                                             static_cast<std::uint8_t>(~(12 + 4 + 2 + 56 + 2))}));
  std::uint8_t be[2];
  scs::PutU16(0x03FF, be);
  EXPECT_EQ(be[0], 0x03);
  EXPECT_EQ(be[1], 0xFF);
  EXPECT_EQ(scs::GetU16(be), 0x03FF);
  const auto write = scs::EncodeWrite(11, scs::reg::kGoalPosition, {0x02, 0x00});
  EXPECT_EQ(write[3], 5);  // address + 2 data + 2
  EXPECT_EQ(write[4], scs::kWrite);
  EXPECT_EQ(write[5], 42);
}

TEST(ScsProtocolTest, SyncWriteLaysOutIdThenDataPerServo) {
  const auto bytes =
      scs::EncodeSyncWrite(42, 6, {{11, {1, 2, 3, 4, 5, 6}}, {12, {7, 8, 9, 10, 11, 12}}});
  ASSERT_EQ(bytes.size(), 4u + 1 + 2 + 2 * 7 + 1);
  EXPECT_EQ(bytes[2], scs::kBroadcastId);
  EXPECT_EQ(bytes[3], 2 + 2 + 2 * 7);  // LEN = params + 2
  EXPECT_EQ(bytes[4], scs::kSyncWrite);
  EXPECT_EQ(bytes[5], 42);
  EXPECT_EQ(bytes[6], 6);
  EXPECT_EQ(bytes[7], 11);
  EXPECT_EQ(bytes[14], 12);
  EXPECT_EQ(bytes.back(), scs::Checksum(bytes.data() + 2, bytes.size() - 3));
}

TEST(ScsProtocolTest, ParserFindsAStatusPacketAfterGarbage) {
  const auto status = scs::Encode({13, scs::kErrorOverload, {0x01, 0x90}});
  std::vector<std::uint8_t> stream = {0x00, 0xFF, 0x12, 0xFF};  // noise, a lone 0xFF
  stream.insert(stream.end(), status.begin(), status.end());
  scs::PacketParser parser;
  const auto results = Feed(&parser, stream);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0], scs::PacketParser::Result::kPacket);
  EXPECT_EQ(parser.packet().id, 13);
  EXPECT_EQ(parser.packet().code, scs::kErrorOverload);
  EXPECT_EQ(parser.packet().params, (std::vector<std::uint8_t>{0x01, 0x90}));
}

TEST(ScsProtocolTest, ParserRejectsACorruptedByteAndRecoversOnTheNextPacket) {
  auto bad = scs::Encode({11, 0, {0x02, 0x00}});
  bad[5] ^= 0x10;
  const auto good = scs::Encode({12, 0, {0x01, 0x00}});
  std::vector<std::uint8_t> stream = bad;
  stream.insert(stream.end(), good.begin(), good.end());
  scs::PacketParser parser;
  const auto results = Feed(&parser, stream);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0], scs::PacketParser::Result::kBadChecksum);
  EXPECT_EQ(results[1], scs::PacketParser::Result::kPacket);
  EXPECT_EQ(parser.packet().id, 12);
}

TEST(ScsProtocolTest, ParserRejectsImpossibleLengths) {
  scs::PacketParser parser;
  EXPECT_EQ(Feed(&parser, {0xFF, 0xFF, 0x01, 0x01}),
            (std::vector<scs::PacketParser::Result>{scs::PacketParser::Result::kBadLength}));
  EXPECT_EQ(Feed(&parser, {0xFF, 0xFF, 0x01, 0xFD}),
            (std::vector<scs::PacketParser::Result>{scs::PacketParser::Result::kBadLength}));
}

TEST(ScsProtocolTest, ErrorBitsAreNamed) {
  EXPECT_EQ(scs::ErrorBitsText(0), "");
  EXPECT_EQ(scs::ErrorBitsText(scs::kErrorOverheat | scs::kErrorOverload), "overheat, overload");
}

TEST(ServoCalibrationTest, TwoMeasuredAnglesMapRawBothWays) {
  const ServoCalibration cal{11, -1.9, 1.9};
  EXPECT_EQ(cal.RawFromAngle(-1.9), 0);
  EXPECT_EQ(cal.RawFromAngle(1.9), 1023);
  EXPECT_EQ(cal.RawFromAngle(0.0), 512);  // 511.5 rounds up
  EXPECT_NEAR(cal.AngleFromRaw(cal.RawFromAngle(0.7)), 0.7, 3.8 / 1023);
  EXPECT_EQ(cal.RawFromAngle(5.0), 1023);  // clamped
  EXPECT_EQ(cal.RawFromAngle(-5.0), 0);
}

TEST(ServoCalibrationTest, AReversedServoCountsDown) {
  const ServoCalibration cal{12, 1.0, -1.0};
  EXPECT_EQ(cal.RawFromAngle(1.0), 0);
  EXPECT_EQ(cal.RawFromAngle(-1.0), 1023);
  EXPECT_NEAR(cal.AngleFromRaw(cal.RawFromAngle(0.3)), 0.3, 2.0 / 1023);
}

}  // namespace
}  // namespace aerograsp
