#include "hardware/scs/scs_bus.h"

#include <chrono>

namespace aerograsp {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

const char* BusStatusName(BusStatus status) {
  switch (status) {
    case BusStatus::kOk:
      return "ok";
    case BusStatus::kTimeout:
      return "timeout";
    case BusStatus::kBadChecksum:
      return "bad checksum";
    case BusStatus::kWriteFailed:
      return "write failed";
  }
  return "unknown";
}

ScsBus::ScsBus(std::unique_ptr<SerialPort> port, double reply_timeout_s, bool local_echo)
    : port_(std::move(port)), reply_timeout_s_(reply_timeout_s), local_echo_(local_echo) {}

BusStatus ScsBus::Send(const std::vector<std::uint8_t>& request) {
  port_->DiscardInput();  // late replies of an earlier exchange
  parser_.Reset();
  if (!port_->Write(request.data(), request.size())) return BusStatus::kWriteFailed;
  if (local_echo_) {  // our own bytes come back first
    std::size_t skipped = 0;
    std::uint8_t buffer[256];
    const auto t0 = std::chrono::steady_clock::now();
    while (skipped < request.size() && SecondsSince(t0) < reply_timeout_s_) {
      const std::size_t want = std::min(sizeof buffer, request.size() - skipped);
      skipped += port_->ReadSome(buffer, want, reply_timeout_s_ - SecondsSince(t0));
    }
  }
  return BusStatus::kOk;
}

BusStatus ScsBus::Exchange(const std::vector<std::uint8_t>& request, std::uint8_t id,
                           std::size_t params, scs::Packet* reply) {
  ++counters_.exchanges;
  const BusStatus sent = Send(request);
  if (sent != BusStatus::kOk) return sent;
  const auto t0 = std::chrono::steady_clock::now();
  bool corrupted = false;
  std::uint8_t buffer[64];
  while (true) {
    const double left = reply_timeout_s_ - SecondsSince(t0);
    if (left <= 0.0) break;
    // One byte at a time would cost a system call per byte; read what is there
    // but never more than the longest reply can hold.
    const std::size_t n = port_->ReadSome(buffer, sizeof buffer, left);
    for (std::size_t i = 0; i < n; ++i) {
      const scs::PacketParser::Result r = parser_.Push(buffer[i]);
      if (r == scs::PacketParser::Result::kBadChecksum ||
          r == scs::PacketParser::Result::kBadLength) {
        corrupted = true;
      } else if (r == scs::PacketParser::Result::kPacket) {
        if (!scs::AnswersExchange(parser_.packet(), id, params)) {
          ++counters_.late_replies;
          continue;
        }
        *reply = parser_.packet();
        return BusStatus::kOk;
      }
    }
  }
  if (corrupted) {
    ++counters_.bad_checksums;
    return BusStatus::kBadChecksum;
  }
  ++counters_.timeouts;
  return BusStatus::kTimeout;
}

BusStatus ScsBus::Ping(std::uint8_t id, std::uint8_t* error) {
  scs::Packet reply;
  const BusStatus status = Exchange(scs::EncodePing(id), id, 0, &reply);
  if (status == BusStatus::kOk && error) *error = reply.code;
  return status;
}

BusStatus ScsBus::Read(std::uint8_t id, std::uint8_t address, std::uint8_t length,
                       std::vector<std::uint8_t>* data, std::uint8_t* error) {
  scs::Packet reply;
  const BusStatus status = Exchange(scs::EncodeRead(id, address, length), id, length, &reply);
  if (status != BusStatus::kOk) return status;
  *data = std::move(reply.params);
  if (error) *error = reply.code;
  return BusStatus::kOk;
}

BusStatus ScsBus::Write(std::uint8_t id, std::uint8_t address,
                        const std::vector<std::uint8_t>& data, std::uint8_t* error) {
  scs::Packet reply;
  const BusStatus status = Exchange(scs::EncodeWrite(id, address, data), id, 0, &reply);
  if (status == BusStatus::kOk && error) *error = reply.code;
  return status;
}

BusStatus ScsBus::SyncWrite(std::uint8_t address, std::uint8_t data_length,
                            const std::vector<scs::SyncEntry>& entries) {
  ++counters_.exchanges;
  return Send(scs::EncodeSyncWrite(address, data_length, entries));
}

}  // namespace aerograsp
