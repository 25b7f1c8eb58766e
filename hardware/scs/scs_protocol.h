// The Feetech SCS servo protocol (docs/hardware.md, Servo bus): packet framing,
// checksum, instructions, the register map and the status error bits. Pure
// functions and a byte-at-a-time parser; no I/O.
//   instruction: 0xFF 0xFF ID LEN INSTR PARAMS... CHECKSUM
//   status:      0xFF 0xFF ID LEN ERROR PARAMS... CHECKSUM
//   LEN = params + 2, CHECKSUM = ~(ID + LEN + INSTR/ERROR + sum(PARAMS)) & 0xFF.
// Multi-byte registers are big-endian.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace aerograsp {
namespace scs {

constexpr std::uint8_t kBroadcastId = 0xFE;
constexpr std::uint8_t kMaxId = 0xFD;
constexpr std::size_t kMaxParams = 250;  // LEN is one byte: params + 2 <= 252

enum Instruction : std::uint8_t {
  kPing = 0x01,
  kRead = 0x02,
  kWrite = 0x03,
  kRegWrite = 0x04,
  kAction = 0x05,
  kReset = 0x06,
  kSyncWrite = 0x83,
};

/// Register addresses (docs/hardware.md).
namespace reg {
constexpr std::uint8_t kId = 5;
constexpr std::uint8_t kBaudRate = 6;
constexpr std::uint8_t kMinAngle = 9;    // 2 bytes
constexpr std::uint8_t kMaxAngle = 11;   // 2 bytes
constexpr std::uint8_t kMaxTorque = 16;  // 2 bytes
constexpr std::uint8_t kTorqueEnable = 40;
constexpr std::uint8_t kGoalPosition = 42;  // 2 bytes
constexpr std::uint8_t kGoalTime = 44;      // 2 bytes
constexpr std::uint8_t kGoalSpeed = 46;     // 2 bytes
constexpr std::uint8_t kLock = 48;
constexpr std::uint8_t kPresentPosition = 56;  // 2 bytes
constexpr std::uint8_t kPresentSpeed = 58;     // 2 bytes
constexpr std::uint8_t kPresentLoad = 60;      // 2 bytes
constexpr std::uint8_t kVoltage = 62;          // 0.1 V
constexpr std::uint8_t kTemperature = 63;      // deg C
constexpr std::uint8_t kMoving = 66;
constexpr std::size_t kCount = 70;  // size of the register map
}  // namespace reg

/// Error bits of a status packet.
enum ErrorBit : std::uint8_t {
  kErrorVoltage = 0x01,
  kErrorAngle = 0x02,
  kErrorOverheat = 0x04,
  kErrorRange = 0x08,
  kErrorChecksum = 0x10,
  kErrorOverload = 0x20,
  kErrorInstruction = 0x40,
};
/// "overheat, overload" for the set bits; "" for none.
std::string ErrorBitsText(std::uint8_t error);

/// ~(sum of bytes) & 0xFF over ID .. last parameter.
std::uint8_t Checksum(const std::uint8_t* from_id, std::size_t size);

/// A whole packet: `code` is the instruction (to a servo) or the error byte (from one).
struct Packet {
  std::uint8_t id = 0;
  std::uint8_t code = 0;
  std::vector<std::uint8_t> params;
};

/// Whether `reply` answers an exchange with servo `id` that waits for `params`
/// parameter bytes. SCS replies carry no sequence number: a reply of another
/// servo, or with another length, is a late reply of an earlier exchange.
inline bool AnswersExchange(const Packet& reply, std::uint8_t id, std::size_t params) {
  return reply.id == id && reply.params.size() == params;
}

/// Frames a packet. Precondition: params.size() <= kMaxParams.
std::vector<std::uint8_t> Encode(const Packet& packet);
std::vector<std::uint8_t> EncodePing(std::uint8_t id);
std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint8_t address, std::uint8_t length);
std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint8_t address,
                                      const std::vector<std::uint8_t>& data);
/// One SYNC_WRITE of `data_length` bytes from `address` to each (id, data).
/// Precondition: every data has data_length bytes; the packet fits kMaxParams.
struct SyncEntry {
  std::uint8_t id;
  std::vector<std::uint8_t> data;
};
std::vector<std::uint8_t> EncodeSyncWrite(std::uint8_t address, std::uint8_t data_length,
                                          const std::vector<SyncEntry>& entries);

/// Big-endian 16-bit helpers.
inline void PutU16(std::uint16_t value, std::uint8_t* out) {
  out[0] = static_cast<std::uint8_t>(value >> 8);
  out[1] = static_cast<std::uint8_t>(value & 0xFF);
}
inline std::uint16_t GetU16(const std::uint8_t* in) {
  return static_cast<std::uint16_t>((in[0] << 8) | in[1]);
}

/// Splits a byte stream into packets: resynchronises on 0xFF 0xFF, rejects
/// bad lengths and checksums. Never reads past what it is given.
class PacketParser {
 public:
  enum class Result { kNeedMore, kPacket, kBadChecksum, kBadLength };
  /// Feeds one byte. On kPacket, packet() holds it until the next Push.
  Result Push(std::uint8_t byte);
  const Packet& packet() const { return packet_; }
  void Reset() { state_ = State::kHeader1; }

 private:
  enum class State { kHeader1, kHeader2, kId, kLength, kBody };
  State state_ = State::kHeader1;
  std::uint8_t length_ = 0;
  std::vector<std::uint8_t> body_;  // code, params, checksum
  Packet packet_;
};

}  // namespace scs
}  // namespace aerograsp
