#include "hardware/mavlink/mavlink_codec.h"

#include <openssl/evp.h>

#include <cassert>
#include <chrono>
#include <cstring>

namespace aerograsp {
namespace mavlink {
namespace {

// CRC_EXTRA and full payload lengths from the MAVLink definitions
// (common.xml / minimal.xml, as the npm package mavlink-mappings carries them).
constexpr MessageInfo kMessages[] = {
    {0, "HEARTBEAT", 50, 9},
    {1, "SYS_STATUS", 124, 43},
    {30, "ATTITUDE", 39, 28},
    {32, "LOCAL_POSITION_NED", 185, 28},
    {76, "COMMAND_LONG", 152, 33},
    {77, "COMMAND_ACK", 143, 10},
    {84, "SET_POSITION_TARGET_LOCAL_NED", 143, 53},
    {85, "POSITION_TARGET_LOCAL_NED", 140, 51},
    {245, "EXTENDED_SYS_STATE", 130, 2},
    {253, "STATUSTEXT", 83, 54},
};

// 2015-01-01T00:00:00Z in Unix seconds.
constexpr std::int64_t kSigningEpoch_s = 1420070400;

void PutTimestamp(std::uint64_t timestamp, std::uint8_t* out) {
  for (int i = 0; i < 6; ++i) out[i] = static_cast<std::uint8_t>(timestamp >> (8 * i));
}

}  // namespace

const MessageInfo* FindMessage(std::uint32_t id) {
  for (const MessageInfo& info : kMessages) {
    if (info.id == id) return &info;
  }
  return nullptr;
}

std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc) {
  std::uint8_t tmp = static_cast<std::uint8_t>(byte ^ (crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ (tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

std::uint16_t Crc(const std::uint8_t* data, std::size_t size, std::uint16_t crc) {
  for (std::size_t i = 0; i < size; ++i) crc = CrcAccumulate(data[i], crc);
  return crc;
}

std::optional<std::array<std::uint8_t, 32>> ParseKeyHex(const std::string& hex) {
  if (hex.size() != 64) return std::nullopt;
  std::array<std::uint8_t, 32> key{};
  auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < 32; ++i) {
    const int hi = nibble(hex[2 * i]), lo = nibble(hex[2 * i + 1]);
    if (hi < 0 || lo < 0) return std::nullopt;
    key[i] = static_cast<std::uint8_t>(hi * 16 + lo);
  }
  return key;
}

std::uint64_t SigningTimestampNow() {
  const auto since_unix = std::chrono::system_clock::now().time_since_epoch();
  const std::int64_t us = std::chrono::duration_cast<std::chrono::microseconds>(since_unix).count();
  return static_cast<std::uint64_t>((us - kSigningEpoch_s * 1000000) / 10);
}

std::array<std::uint8_t, 6> Signature(const std::array<std::uint8_t, 32>& secret,
                                      const std::uint8_t* frame_to_link_id, std::size_t size,
                                      std::uint64_t timestamp) {
  std::uint8_t stamp[6];
  PutTimestamp(timestamp, stamp);
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  std::uint8_t digest[EVP_MAX_MD_SIZE];
  unsigned digest_length = 0;
  EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
  EVP_DigestUpdate(ctx, secret.data(), secret.size());
  EVP_DigestUpdate(ctx, frame_to_link_id, size);
  EVP_DigestUpdate(ctx, stamp, sizeof stamp);
  EVP_DigestFinal_ex(ctx, digest, &digest_length);
  EVP_MD_CTX_free(ctx);
  std::array<std::uint8_t, 6> out;
  std::memcpy(out.data(), digest, out.size());
  return out;
}

std::vector<std::uint8_t> Encoder::Encode(std::uint32_t msgid,
                                          const std::vector<std::uint8_t>& payload,
                                          std::optional<std::uint64_t> timestamp) {
  const MessageInfo* info = FindMessage(msgid);
  assert(info != nullptr && payload.size() <= kMaxPayload);
  std::size_t length = payload.size();
  while (length > 1 && payload[length - 1] == 0) --length;  // MAVLink 2 payload truncation
  std::vector<std::uint8_t> out;
  out.reserve(kHeaderLength + length + 2 + kSignatureLength);
  out.push_back(kStxV2);
  out.push_back(static_cast<std::uint8_t>(length));
  out.push_back(key_ ? kIncompatSigned : 0);
  out.push_back(0);
  out.push_back(seq_++);
  out.push_back(sysid_);
  out.push_back(compid_);
  out.push_back(static_cast<std::uint8_t>(msgid & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 8) & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 16) & 0xFF));
  for (std::size_t i = 0; i < length; ++i) out.push_back(payload[i]);
  std::uint16_t crc = Crc(out.data() + 1, out.size() - 1);
  crc = CrcAccumulate(info->crc_extra, crc);
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  if (key_) {
    std::uint64_t stamp = timestamp ? *timestamp : SigningTimestampNow();
    if (stamp <= last_timestamp_) stamp = last_timestamp_ + 1;  // strictly increasing per link
    last_timestamp_ = stamp;
    out.push_back(key_->link_id);
    const std::array<std::uint8_t, 6> sig = Signature(key_->secret, out.data(), out.size(), stamp);
    std::uint8_t bytes[6];
    PutTimestamp(stamp, bytes);
    out.insert(out.end(), bytes, bytes + 6);
    out.insert(out.end(), sig.begin(), sig.end());
  }
  return out;
}

Parser::Result Parser::Push(std::uint8_t byte) {
  if (buffer_.empty()) {
    if (byte == kStxV2) buffer_.push_back(byte);
    return Result::kNeedMore;
  }
  buffer_.push_back(byte);
  if (buffer_.size() == kHeaderLength) {
    const std::uint8_t incompat = buffer_[2];
    if (incompat & ~kIncompatSigned) {  // a flag we do not understand: we cannot parse the frame
      buffer_.clear();
      ++counters_.unsupported_flags;
      return Result::kUnsupportedFlags;
    }
    expected_ =
        kHeaderLength + buffer_[1] + 2 + ((incompat & kIncompatSigned) ? kSignatureLength : 0);
  }
  if (buffer_.size() < kHeaderLength || buffer_.size() < expected_) return Result::kNeedMore;
  const Result result = Finish();
  buffer_.clear();
  return result;
}

Parser::Result Parser::Finish() {
  const std::uint8_t length = buffer_[1];
  const std::uint32_t msgid =
      buffer_[7] | (buffer_[8] << 8) | (static_cast<std::uint32_t>(buffer_[9]) << 16);
  const MessageInfo* info = FindMessage(msgid);
  if (!info) {
    ++counters_.unknown_message;
    return Result::kUnknownMessage;
  }
  const std::size_t crc_at = kHeaderLength + length;
  std::uint16_t crc = Crc(buffer_.data() + 1, crc_at - 1);
  crc = CrcAccumulate(info->crc_extra, crc);
  if ((crc & 0xFF) != buffer_[crc_at] || (crc >> 8) != buffer_[crc_at + 1]) {
    ++counters_.bad_crc;
    return Result::kBadCrc;
  }
  const bool is_signed = buffer_[2] & kIncompatSigned;
  std::uint8_t link_id = 0;
  std::uint64_t timestamp = 0;
  if (is_signed) {
    link_id = buffer_[crc_at + 2];
    for (int i = 0; i < 6; ++i)
      timestamp |= static_cast<std::uint64_t>(buffer_[crc_at + 3 + i]) << (8 * i);
  }
  if (secret_) {
    if (!is_signed) {
      ++counters_.bad_signature;
      return Result::kBadSignature;
    }
    const std::array<std::uint8_t, 6> expected =
        Signature(*secret_, buffer_.data(), crc_at + 3, timestamp);
    const auto key = std::make_tuple(buffer_[5], buffer_[6], link_id);
    const auto last = last_timestamps_.find(key);
    if (std::memcmp(expected.data(), buffer_.data() + crc_at + 9, 6) != 0 ||
        (last != last_timestamps_.end() && timestamp <= last->second)) {
      ++counters_.bad_signature;
      return Result::kBadSignature;
    }
    last_timestamps_[key] = timestamp;
  }
  frame_.incompat_flags = buffer_[2];
  frame_.compat_flags = buffer_[3];
  frame_.seq = buffer_[4];
  frame_.sysid = buffer_[5];
  frame_.compid = buffer_[6];
  frame_.msgid = msgid;
  frame_.payload.assign(buffer_.begin() + kHeaderLength,
                        buffer_.begin() + static_cast<std::ptrdiff_t>(crc_at));
  frame_.is_signed = is_signed;
  frame_.link_id = link_id;
  frame_.timestamp = timestamp;
  ++counters_.frames;
  return Result::kFrame;
}

}  // namespace mavlink
}  // namespace aerograsp
