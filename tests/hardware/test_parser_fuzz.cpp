// Randomised robustness of the two wire parsers: random bytes, valid frames
// with random corruption, truncation and splicing. No crash, no hang, nothing
// read past a buffer (run under -fsanitize=address to see the last; see also
// tests/fuzz/ for the libFuzzer targets).
#include <gtest/gtest.h>

#include <random>

#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_messages.h"
#include "hardware/scs/scs_protocol.h"

namespace aerograsp {
namespace {

/// Decodes a frame into every message type, whatever its id says: the reader
/// must cope with payloads of any length.
void UnpackAsEverything(const mavlink::Frame& frame) {
  using namespace mavlink;
  (void)Unpack<Heartbeat>(frame);
  (void)Unpack<SysStatus>(frame);
  (void)Unpack<Attitude>(frame);
  (void)Unpack<LocalPositionNed>(frame);
  (void)Unpack<CommandLong>(frame);
  (void)Unpack<CommandAck>(frame);
  (void)Unpack<SetPositionTargetLocalNed>(frame);
  (void)Unpack<PositionTargetLocalNed>(frame);
  (void)Unpack<ExtendedSysState>(frame);
  (void)Unpack<StatusText>(frame).Text();
}

std::vector<std::uint8_t> Mutate(std::vector<std::uint8_t> bytes, std::mt19937_64* rng) {
  std::uniform_int_distribution<int> kind(0, 3), byte(0, 255);
  switch (kind(*rng)) {
    case 0:  // flip bytes
      for (int k = 0; k < 3 && !bytes.empty(); ++k)
        bytes[(*rng)() % bytes.size()] = static_cast<std::uint8_t>(byte(*rng));
      break;
    case 1:  // truncate
      if (!bytes.empty()) bytes.resize((*rng)() % bytes.size());
      break;
    case 2:  // a random length byte
      if (bytes.size() > 1) bytes[1] = static_cast<std::uint8_t>(byte(*rng));
      break;
    default:  // intact
      break;
  }
  return bytes;
}

TEST(ParserFuzzTest, MavlinkParserSurvivesNoiseAndBrokenFrames) {
  std::mt19937_64 rng(20260801);
  std::uniform_int_distribution<int> byte(0, 255);
  mavlink::Encoder encoder(1, 1);
  mavlink::Encoder signer(1, 1);
  signer.SetSigning(mavlink::SigningKey{{}, 1});
  mavlink::Parser parser, strict;
  strict.RequireSigning(std::array<std::uint8_t, 32>{});
  std::int64_t frames = 0;
  for (int round = 0; round < 20000; ++round) {
    std::vector<std::uint8_t> bytes;
    if (round % 4 == 0) {
      for (int i = 0; i < 64; ++i) bytes.push_back(static_cast<std::uint8_t>(byte(rng)));
      if (round % 8 == 0) bytes[rng() % bytes.size()] = mavlink::kStxV2;
    } else {
      mavlink::CommandLong cmd;
      cmd.param1 = static_cast<float>(round);
      cmd.command = static_cast<std::uint16_t>(rng());
      bytes = (round % 3 ? encoder : signer).Encode(mavlink::CommandLong::kId, mavlink::Pack(cmd));
      bytes = Mutate(bytes, &rng);
    }
    for (std::uint8_t b : bytes) {
      for (mavlink::Parser* p : {&parser, &strict}) {
        if (p->Push(b) == mavlink::Parser::Result::kFrame) {
          ASSERT_LE(p->frame().payload.size(), mavlink::kMaxPayload);
          UnpackAsEverything(p->frame());
          ++frames;
        }
      }
    }
  }
  EXPECT_GT(frames, 1000);  // intact frames got through
  EXPECT_GT(parser.counters().bad_crc, 0);
}

TEST(ParserFuzzTest, ScsParserSurvivesNoiseAndBrokenPackets) {
  std::mt19937_64 rng(77);
  std::uniform_int_distribution<int> byte(0, 255);
  scs::PacketParser parser;
  std::int64_t packets = 0;
  for (int round = 0; round < 20000; ++round) {
    std::vector<std::uint8_t> bytes;
    if (round % 4 == 0) {
      for (int i = 0; i < 32; ++i) bytes.push_back(static_cast<std::uint8_t>(byte(rng)));
    } else {
      std::vector<std::uint8_t> params(rng() % 8);
      for (auto& p : params) p = static_cast<std::uint8_t>(byte(rng));
      bytes = Mutate(scs::Encode({static_cast<std::uint8_t>(rng() % 254), 0, params}), &rng);
    }
    for (std::uint8_t b : bytes) {
      if (parser.Push(b) == scs::PacketParser::Result::kPacket) {
        ASSERT_LE(parser.packet().params.size(), scs::kMaxParams);
        ++packets;
      }
    }
  }
  EXPECT_GT(packets, 1000);
}

}  // namespace
}  // namespace aerograsp
