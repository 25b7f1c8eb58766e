#include "hardware/scs/scs_protocol.h"

#include <cassert>

namespace aerograsp {
namespace scs {

std::string ErrorBitsText(std::uint8_t error) {
  static const char* const kNames[] = {"input voltage", "angle limit", "overheat",    "range",
                                       "checksum",      "overload",    "instruction", "bit 7"};
  std::string text;
  for (int bit = 0; bit < 8; ++bit) {
    if (!(error & (1u << bit))) continue;
    if (!text.empty()) text += ", ";
    text += kNames[bit];
  }
  return text;
}

std::uint8_t Checksum(const std::uint8_t* from_id, std::size_t size) {
  unsigned sum = 0;
  for (std::size_t i = 0; i < size; ++i) sum += from_id[i];
  return static_cast<std::uint8_t>(~sum & 0xFF);
}

std::vector<std::uint8_t> Encode(const Packet& packet) {
  assert(packet.params.size() <= kMaxParams);
  std::vector<std::uint8_t> out;
  out.reserve(packet.params.size() + 6);
  out.push_back(0xFF);
  out.push_back(0xFF);
  out.push_back(packet.id);
  out.push_back(static_cast<std::uint8_t>(packet.params.size() + 2));
  out.push_back(packet.code);
  out.insert(out.end(), packet.params.begin(), packet.params.end());
  out.push_back(Checksum(out.data() + 2, out.size() - 2));
  return out;
}

std::vector<std::uint8_t> EncodePing(std::uint8_t id) { return Encode({id, kPing, {}}); }

std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint8_t address, std::uint8_t length) {
  return Encode({id, kRead, {address, length}});
}

std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint8_t address,
                                      const std::vector<std::uint8_t>& data) {
  Packet p{id, kWrite, {}};
  p.params.reserve(data.size() + 1);
  p.params.push_back(address);
  for (std::uint8_t b : data) p.params.push_back(b);  // (insert() trips GCC 12's -Warray-bounds)
  return Encode(p);
}

std::vector<std::uint8_t> EncodeSyncWrite(std::uint8_t address, std::uint8_t data_length,
                                          const std::vector<SyncEntry>& entries) {
  Packet p{kBroadcastId, kSyncWrite, {address, data_length}};
  for (const SyncEntry& e : entries) {
    assert(e.data.size() == data_length);
    p.params.push_back(e.id);
    p.params.insert(p.params.end(), e.data.begin(), e.data.end());
  }
  return Encode(p);
}

PacketParser::Result PacketParser::Push(std::uint8_t byte) {
  switch (state_) {
    case State::kHeader1:
      if (byte == 0xFF) state_ = State::kHeader2;
      return Result::kNeedMore;
    case State::kHeader2:
      state_ = byte == 0xFF ? State::kId : State::kHeader1;
      return Result::kNeedMore;
    case State::kId:
      if (byte == 0xFF) return Result::kNeedMore;  // a third 0xFF: still in the header
      packet_.id = byte;
      state_ = State::kLength;
      return Result::kNeedMore;
    case State::kLength:
      if (byte < 2 || byte > kMaxParams + 2) {
        state_ = State::kHeader1;
        return Result::kBadLength;
      }
      length_ = byte;
      body_.clear();
      state_ = State::kBody;
      return Result::kNeedMore;
    case State::kBody: {
      body_.push_back(byte);
      if (body_.size() < length_) return Result::kNeedMore;
      state_ = State::kHeader1;
      unsigned sum = packet_.id + length_;
      for (std::size_t i = 0; i + 1 < body_.size(); ++i) sum += body_[i];
      if (static_cast<std::uint8_t>(~sum & 0xFF) != body_.back()) return Result::kBadChecksum;
      packet_.code = body_[0];
      packet_.params.assign(body_.begin() + 1, body_.end() - 1);
      return Result::kPacket;
    }
  }
  return Result::kNeedMore;
}

}  // namespace scs
}  // namespace aerograsp
