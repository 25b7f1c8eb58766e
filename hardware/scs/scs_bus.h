// The master end of an SCS servo bus: one exchange at a time (half duplex),
// each with a reply timeout. Runs inside a control loop, so failures are
// status values, never exceptions (STYLE.md, errors by layer).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hardware/scs/scs_protocol.h"
#include "hardware/serial_port.h"

namespace aerograsp {

enum class BusStatus {
  kOk,
  kTimeout,      ///< no (complete) reply in time: silent or absent servo
  kBadChecksum,  ///< a reply arrived corrupted
  kWriteFailed,  ///< the port refused the bytes
};
const char* BusStatusName(BusStatus status);

struct BusCounters {
  std::int64_t exchanges = 0;
  std::int64_t timeouts = 0;
  std::int64_t bad_checksums = 0;  ///< exchanges whose reply came corrupted (checksum, length)
  /// Well-formed replies that answer no request of theirs (another servo's
  /// id, or another size): a reply that came after its exchange's timeout,
  /// already counted there as a timeout. Skipped, never corruption.
  std::int64_t late_replies = 0;
};

class ScsBus {
 public:
  /// `reply_timeout_s`: how long to wait for a status packet, (0, 1] s.
  /// `local_echo`: the adapter echoes what it sends (one-wire TTL boards do); skip it.
  ScsBus(std::unique_ptr<SerialPort> port, double reply_timeout_s, bool local_echo = false);

  const std::string& port_path() const { return port_->path(); }
  /// `error` (may be null) gets the servo's error bits on kOk.
  BusStatus Ping(std::uint8_t id, std::uint8_t* error = nullptr);
  /// Reads `length` bytes from `address` into `data`.
  BusStatus Read(std::uint8_t id, std::uint8_t address, std::uint8_t length,
                 std::vector<std::uint8_t>* data, std::uint8_t* error = nullptr);
  /// Writes and waits for the status reply.
  BusStatus Write(std::uint8_t id, std::uint8_t address, const std::vector<std::uint8_t>& data,
                  std::uint8_t* error = nullptr);
  /// Broadcast SYNC_WRITE: no reply.
  BusStatus SyncWrite(std::uint8_t address, std::uint8_t data_length,
                      const std::vector<scs::SyncEntry>& entries);
  const BusCounters& counters() const { return counters_; }

 private:
  /// Sends `request` and waits for the reply of servo `id` holding `params`
  /// parameter bytes; other well-formed replies are late ones: skipped.
  BusStatus Exchange(const std::vector<std::uint8_t>& request, std::uint8_t id, std::size_t params,
                     scs::Packet* reply);
  BusStatus Send(const std::vector<std::uint8_t>& request);

  std::unique_ptr<SerialPort> port_;
  double reply_timeout_s_;
  bool local_echo_;
  scs::PacketParser parser_;
  BusCounters counters_;
};

}  // namespace aerograsp
