#include <gtest/gtest.h>

#include <cmath>

#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_messages.h"

namespace aerograsp {
namespace mavlink {
namespace {

const std::string kKeyHex = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

std::vector<Parser::Result> FeedAll(Parser* parser, const std::vector<std::uint8_t>& bytes,
                                    std::vector<Frame>* frames = nullptr) {
  std::vector<Parser::Result> results;
  for (std::uint8_t b : bytes) {
    const Parser::Result r = parser->Push(b);
    if (r == Parser::Result::kNeedMore) continue;
    results.push_back(r);
    if (r == Parser::Result::kFrame && frames) frames->push_back(parser->frame());
  }
  return results;
}

template <class M>
M RoundTrip(const M& message) {
  Encoder encoder(1, 191);
  Parser parser;
  std::vector<Frame> frames;
  const auto results = FeedAll(&parser, encoder.Encode(M::kId, Pack(message)), &frames);
  EXPECT_EQ(results, std::vector<Parser::Result>{Parser::Result::kFrame});
  if (frames.empty()) return M{};
  EXPECT_EQ(frames[0].msgid, M::kId);
  return Unpack<M>(frames[0]);
}

TEST(MavlinkCodecTest, CrcIsMcrf4xx) {
  const std::string check = "123456789";
  EXPECT_EQ(Crc(reinterpret_cast<const std::uint8_t*>(check.data()), check.size()), 0x6F91);
}

TEST(MavlinkCodecTest, PayloadLengthsMatchTheMessageDefinitions) {
  EXPECT_EQ(Pack(Heartbeat{}).size(), FindMessage(Heartbeat::kId)->length);
  EXPECT_EQ(Pack(SysStatus{}).size(), FindMessage(SysStatus::kId)->length);
  EXPECT_EQ(Pack(Attitude{}).size(), FindMessage(Attitude::kId)->length);
  EXPECT_EQ(Pack(LocalPositionNed{}).size(), FindMessage(LocalPositionNed::kId)->length);
  EXPECT_EQ(Pack(CommandLong{}).size(), FindMessage(CommandLong::kId)->length);
  EXPECT_EQ(Pack(CommandAck{}).size(), FindMessage(CommandAck::kId)->length);
  EXPECT_EQ(Pack(SetPositionTargetLocalNed{}).size(),
            FindMessage(SetPositionTargetLocalNed::kId)->length);
  EXPECT_EQ(Pack(PositionTargetLocalNed{}).size(),
            FindMessage(PositionTargetLocalNed::kId)->length);
  EXPECT_EQ(Pack(ExtendedSysState{}).size(), FindMessage(ExtendedSysState::kId)->length);
  EXPECT_EQ(Pack(StatusText{}).size(), FindMessage(StatusText::kId)->length);
}

TEST(MavlinkCodecTest, HeaderCarriesSequenceIdsAndMessageId) {
  Encoder encoder(7, 191);
  encoder.Encode(Heartbeat::kId, Pack(Heartbeat{}));
  const auto bytes = encoder.Encode(CommandLong::kId, Pack(CommandLong{}));
  EXPECT_EQ(bytes[0], kStxV2);
  EXPECT_EQ(bytes[2], 0);  // incompat flags: unsigned
  EXPECT_EQ(bytes[4], 1);  // second frame
  EXPECT_EQ(bytes[5], 7);
  EXPECT_EQ(bytes[6], 191);
  EXPECT_EQ(bytes[7], 76);
  EXPECT_EQ(bytes[8], 0);
  EXPECT_EQ(bytes[9], 0);
}

TEST(MavlinkCodecTest, TrailingZerosAreCutAndRestoredAsZeros) {
  CommandAck ack;
  ack.command = 400;
  ack.result = kResultAccepted;  // 0, and every extension 0: payload is the command only
  Encoder encoder(1, 1);
  const auto bytes = encoder.Encode(CommandAck::kId, Pack(ack));
  EXPECT_EQ(bytes[1], 2);
  const CommandAck back = RoundTrip(ack);
  EXPECT_EQ(back.command, 400);
  EXPECT_EQ(back.result, 0);
  EXPECT_EQ(back.target_system, 0);
  Heartbeat zero{};
  zero.mavlink_version = 0;
  EXPECT_EQ(encoder.Encode(Heartbeat::kId, Pack(zero))[1], 1);  // one byte is always kept
}

TEST(MavlinkCodecTest, EveryMessageSurvivesARoundTrip) {
  SetPositionTargetLocalNed sp;
  sp.time_boot_ms = 123456;
  sp.x = 1.5f, sp.y = -2.25f, sp.z = -3.0f, sp.yaw = 0.75f;
  sp.type_mask = kTypeMaskPositionYaw;
  sp.target_system = 1, sp.target_component = 1, sp.coordinate_frame = kFrameLocalNed;
  const auto sp2 = RoundTrip(sp);
  EXPECT_EQ(sp2.time_boot_ms, 123456u);
  EXPECT_EQ(sp2.x, 1.5f);
  EXPECT_EQ(sp2.y, -2.25f);
  EXPECT_EQ(sp2.z, -3.0f);
  EXPECT_EQ(sp2.yaw, 0.75f);
  EXPECT_EQ(sp2.type_mask, kTypeMaskPositionYaw);
  EXPECT_EQ(sp2.coordinate_frame, kFrameLocalNed);

  CommandLong cmd;
  cmd.param1 = 1.0f, cmd.param7 = std::nanf("");
  cmd.command = kCmdComponentArmDisarm, cmd.target_system = 1, cmd.target_component = 1,
  cmd.confirmation = 2;
  const auto cmd2 = RoundTrip(cmd);
  EXPECT_EQ(cmd2.param1, 1.0f);
  EXPECT_TRUE(std::isnan(cmd2.param7));
  EXPECT_EQ(cmd2.command, kCmdComponentArmDisarm);
  EXPECT_EQ(cmd2.confirmation, 2);

  Heartbeat hb;
  hb.custom_mode = px4::CustomMode(px4::kMainAuto, px4::kAutoLoiter);
  hb.type = 13, hb.autopilot = 12, hb.base_mode = 129, hb.system_status = 4;
  const auto hb2 = RoundTrip(hb);
  EXPECT_EQ(px4::MainMode(hb2.custom_mode), px4::kMainAuto);
  EXPECT_EQ(px4::SubMode(hb2.custom_mode), px4::kAutoLoiter);
  EXPECT_EQ(hb2.base_mode, 129);

  SysStatus status;
  status.voltage_battery = 16800, status.current_battery = -1, status.battery_remaining = -1;
  status.sensors_health_extended = 0xABCD;
  const auto status2 = RoundTrip(status);
  EXPECT_EQ(status2.voltage_battery, 16800);
  EXPECT_EQ(status2.current_battery, -1);
  EXPECT_EQ(status2.battery_remaining, -1);
  EXPECT_EQ(status2.sensors_health_extended, 0xABCDu);

  StatusText text;
  text.severity = 4;
  text.SetText("Arming denied: not ready");
  text.id = 9;
  EXPECT_EQ(RoundTrip(text).Text(), "Arming denied: not ready");
  EXPECT_EQ(RoundTrip(text).id, 9);
  text.SetText(std::string(60, 'x'));  // longer than the field: cut at 50, no terminator
  EXPECT_EQ(RoundTrip(text).Text(), std::string(50, 'x'));

  Attitude att;
  att.roll = 0.1f, att.yawspeed = -0.2f;
  EXPECT_EQ(RoundTrip(att).yawspeed, -0.2f);
  LocalPositionNed pos;
  pos.z = -2.0f, pos.vx = 0.5f;
  EXPECT_EQ(RoundTrip(pos).vx, 0.5f);
  ExtendedSysState ext;
  ext.landed_state = kLandedInAir;
  EXPECT_EQ(RoundTrip(ext).landed_state, kLandedInAir);
  PositionTargetLocalNed target;
  target.coordinate_frame = kFrameLocalNed, target.afz = 9.0f;
  EXPECT_EQ(RoundTrip(target).afz, 9.0f);
}

TEST(MavlinkCodecTest, ParserRejectsACorruptedFrameAndReadsTheNext) {
  Encoder encoder(1, 1);
  auto bad = encoder.Encode(Attitude::kId, Pack(Attitude{1, 0.1f}));
  bad[12] ^= 0x04;
  const auto good = encoder.Encode(ExtendedSysState::kId, Pack(ExtendedSysState{0, kLandedInAir}));
  std::vector<std::uint8_t> stream = {0x00, 0x42};
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), good.begin(), good.end());
  Parser parser;
  std::vector<Frame> frames;
  EXPECT_EQ(FeedAll(&parser, stream, &frames),
            (std::vector<Parser::Result>{Parser::Result::kBadCrc, Parser::Result::kFrame}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].msgid, ExtendedSysState::kId);
  EXPECT_EQ(parser.counters().bad_crc, 1);
}

TEST(MavlinkCodecTest, UnknownMessagesAndFlagsAreDropped) {
  // A frame of message 9999 (its CRC cannot be checked without CRC_EXTRA).
  std::vector<std::uint8_t> unknown = {kStxV2, 1,    0,    0,    0,    1,   1,
                                       0x0F,   0x27, 0x00, 0x55, 0x00, 0x00};
  Parser parser;
  EXPECT_EQ(FeedAll(&parser, unknown),
            std::vector<Parser::Result>{Parser::Result::kUnknownMessage});
  std::vector<std::uint8_t> flags = {kStxV2, 1, 0x02, 0, 0, 1, 1, 0, 0, 0};
  EXPECT_EQ(FeedAll(&parser, flags),
            std::vector<Parser::Result>{Parser::Result::kUnsupportedFlags});
}

TEST(MavlinkCodecTest, SignedFramesVerifyAndOthersAreRefused) {
  const auto key = ParseKeyHex(kKeyHex);
  ASSERT_TRUE(key);
  Encoder signer(1, 191);
  signer.SetSigning(SigningKey{*key, 3});
  const auto frame1 = signer.Encode(Heartbeat::kId, Pack(Heartbeat{}), 1000);
  EXPECT_EQ(frame1[2], kIncompatSigned);
  EXPECT_EQ(frame1.size(), kHeaderLength + frame1[1] + 2 + kSignatureLength);
  const auto frame2 = signer.Encode(Heartbeat::kId, Pack(Heartbeat{}), 2000);

  Parser verifier;
  verifier.RequireSigning(*key);
  std::vector<Frame> frames;
  EXPECT_EQ(FeedAll(&verifier, frame1, &frames),
            std::vector<Parser::Result>{Parser::Result::kFrame});
  EXPECT_TRUE(frames[0].is_signed);
  EXPECT_EQ(frames[0].link_id, 3);
  EXPECT_EQ(frames[0].timestamp, 1000u);
  // A replay of the same frame is refused; the next one is fine.
  EXPECT_EQ(FeedAll(&verifier, frame1), std::vector<Parser::Result>{Parser::Result::kBadSignature});
  EXPECT_EQ(FeedAll(&verifier, frame2), std::vector<Parser::Result>{Parser::Result::kFrame});

  auto wrong_key = *key;
  wrong_key[0] ^= 1;
  Parser other;
  other.RequireSigning(wrong_key);
  EXPECT_EQ(FeedAll(&other, frame2), std::vector<Parser::Result>{Parser::Result::kBadSignature});
  Encoder plain(1, 191);
  EXPECT_EQ(FeedAll(&verifier, plain.Encode(Heartbeat::kId, Pack(Heartbeat{}))),
            std::vector<Parser::Result>{Parser::Result::kBadSignature});
  // A parser without a key reads signed frames (and ignores the signature).
  Parser open;
  EXPECT_EQ(FeedAll(&open, frame1), std::vector<Parser::Result>{Parser::Result::kFrame});
}

TEST(MavlinkCodecTest, KeysAreSixtyFourHexDigits) {
  EXPECT_TRUE(ParseKeyHex(kKeyHex));
  EXPECT_FALSE(ParseKeyHex("00"));
  EXPECT_FALSE(ParseKeyHex(std::string(63, '0') + "g"));
}

}  // namespace
}  // namespace mavlink
}  // namespace aerograsp
