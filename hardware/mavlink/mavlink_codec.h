// MAVLink 2 framing (no generated headers): CRC-16/MCRF4XX with each
// message's CRC_EXTRA, payload truncation of trailing zeros, incompatibility
// flags, and optional packet signing (SHA-256, 6-byte signature).
//   STX(0xFD) LEN INCOMPAT COMPAT SEQ SYSID COMPID MSGID(3, LE) PAYLOAD CRC(2, LE) [SIGNATURE(13)]
//   signature: LINK_ID TIMESTAMP(6, LE, 10 us since 2015-01-01) SHA256(key, frame..link_id,
//   timestamp)[0..5]
// The parser never reads past what it was given and keeps at most one frame.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace aerograsp {
namespace mavlink {

constexpr std::uint8_t kStxV2 = 0xFD;
constexpr std::uint8_t kIncompatSigned = 0x01;
constexpr std::size_t kHeaderLength = 10;  // STX .. MSGID
constexpr std::size_t kSignatureLength = 13;
constexpr std::size_t kMaxPayload = 255;

/// What the codec needs to know of a message type.
struct MessageInfo {
  std::uint32_t id;
  const char* name;
  std::uint8_t crc_extra;
  std::uint8_t length;  ///< full payload length with extensions
};
/// The messages this project speaks (docs/hardware.md); null for others.
const MessageInfo* FindMessage(std::uint32_t id);

/// CRC-16/MCRF4XX (X.25) as MAVLink accumulates it.
std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc);
std::uint16_t Crc(const std::uint8_t* data, std::size_t size, std::uint16_t crc = 0xFFFF);

struct SigningKey {
  std::array<std::uint8_t, 32> secret{};
  std::uint8_t link_id = 0;
};
/// 32 bytes from 64 hex digits. Returns nullopt when the text is not that.
std::optional<std::array<std::uint8_t, 32>> ParseKeyHex(const std::string& hex);

struct Frame {
  std::uint8_t incompat_flags = 0;
  std::uint8_t compat_flags = 0;
  std::uint8_t seq = 0;
  std::uint8_t sysid = 0;
  std::uint8_t compid = 0;
  std::uint32_t msgid = 0;
  std::vector<std::uint8_t> payload;  ///< as on the wire (trailing zeros may be cut)
  bool is_signed = false;
  std::uint8_t link_id = 0;
  std::uint64_t timestamp = 0;  ///< 10 us units since 2015-01-01 (48 bits)
};

/// Serialises frames of one sender and counts its sequence.
class Encoder {
 public:
  Encoder(std::uint8_t sysid, std::uint8_t compid) : sysid_(sysid), compid_(compid) {}
  /// Signs every following frame (nullopt: stop signing).
  void SetSigning(const std::optional<SigningKey>& key) { key_ = key; }
  /// Frames `payload` (at most kMaxPayload bytes; trailing zeros are cut, one byte kept).
  /// `timestamp` is used when signing (must grow; SigningTimestampNow() by default).
  /// Precondition: FindMessage(msgid) is not null.
  std::vector<std::uint8_t> Encode(std::uint32_t msgid, const std::vector<std::uint8_t>& payload,
                                   std::optional<std::uint64_t> timestamp = std::nullopt);
  std::uint8_t next_seq() const { return seq_; }

 private:
  std::uint8_t sysid_, compid_, seq_ = 0;
  std::optional<SigningKey> key_;
  std::uint64_t last_timestamp_ = 0;
};

/// The signing timestamp of now (10 us since 2015-01-01 00:00 UTC).
std::uint64_t SigningTimestampNow();
/// The 6-byte signature of a frame whose bytes up to and including the link id
/// are `frame_to_link_id`.
std::array<std::uint8_t, 6> Signature(const std::array<std::uint8_t, 32>& secret,
                                      const std::uint8_t* frame_to_link_id, std::size_t size,
                                      std::uint64_t timestamp);

struct ParserCounters {
  std::int64_t frames = 0;
  std::int64_t bad_crc = 0;
  std::int64_t unknown_message = 0;  ///< CRC cannot be checked without CRC_EXTRA: dropped
  std::int64_t bad_signature = 0;    ///< wrong, missing when required, or replayed timestamp
  std::int64_t unsupported_flags = 0;
};

/// Splits bytes into frames. Resynchronises on the next STX after any error.
class Parser {
 public:
  enum class Result {
    kNeedMore,
    kFrame,
    kBadCrc,
    kUnknownMessage,
    kBadSignature,
    kUnsupportedFlags
  };
  /// With a key, only frames signed with it (and with a timestamp newer than
  /// the last from the same sysid, compid, link) are accepted.
  void RequireSigning(const std::optional<std::array<std::uint8_t, 32>>& secret) {
    secret_ = secret;
  }
  Result Push(std::uint8_t byte);
  /// Valid after kFrame until the next Push.
  const Frame& frame() const { return frame_; }
  const ParserCounters& counters() const { return counters_; }

 private:
  Result Finish();
  std::vector<std::uint8_t> buffer_;  // the frame being read, from STX
  std::size_t expected_ = 0;          // its full length once the header is in
  Frame frame_;
  ParserCounters counters_;
  std::optional<std::array<std::uint8_t, 32>> secret_;
  std::map<std::tuple<std::uint8_t, std::uint8_t, std::uint8_t>, std::uint64_t> last_timestamps_;
};

}  // namespace mavlink
}  // namespace aerograsp
