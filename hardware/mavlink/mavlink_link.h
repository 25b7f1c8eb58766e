// Byte transports for MAVLink: UDP (PX4 SITL and telemetry radios with a
// network bridge) and a serial port (the Pixhawk's TELEM2 to the companion).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hardware/serial_port.h"

namespace aerograsp {

class MavlinkLink {
 public:
  virtual ~MavlinkLink() = default;
  /// Sends one frame. False when it could not (no peer yet, I/O error).
  virtual bool Send(const std::vector<std::uint8_t>& bytes) = 0;
  /// Receives what is available, waiting up to `timeout_s`; 0 bytes on timeout.
  virtual std::size_t Receive(std::uint8_t* data, std::size_t capacity, double timeout_s) = 0;
  /// "udp 127.0.0.1:14540 -> 127.0.0.1:14580", "serial /dev/ttyACM0 921600".
  virtual std::string Describe() const = 0;
};

/// UDP on IPv4. Binds `local_host:local_port` (port 0: any free port). Sends to
/// `remote_host:remote_port`; with remote_port 0 it answers whoever sent the
/// last datagram (as PX4 SITL's companion link expects).
class UdpLink : public MavlinkLink {
 public:
  /// @throws HardwareError "<device>: cannot bind udp <host>:<port>: <reason>".
  UdpLink(const std::string& local_host, int local_port, const std::string& remote_host,
          int remote_port, const std::string& device);
  ~UdpLink() override;
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  bool Send(const std::vector<std::uint8_t>& bytes) override;
  std::size_t Receive(std::uint8_t* data, std::size_t capacity, double timeout_s) override;
  std::string Describe() const override;
  /// The bound port (useful with local_port 0).
  int local_port() const { return local_port_; }

 private:
  int fd_ = -1;
  std::string local_host_;
  int local_port_ = 0;
  mutable std::mutex remote_mutex_;  // Send and Receive may run on different threads
  bool has_remote_ = false;
  unsigned char remote_[16] = {};  // sockaddr_in
};

class SerialLink : public MavlinkLink {
 public:
  /// @throws HardwareError naming the device and the port.
  SerialLink(const std::string& path, int baud, const std::string& device);
  bool Send(const std::vector<std::uint8_t>& bytes) override {
    return port_.Write(bytes.data(), bytes.size());
  }
  std::size_t Receive(std::uint8_t* data, std::size_t capacity, double timeout_s) override {
    return port_.ReadSome(data, capacity, timeout_s);
  }
  std::string Describe() const override {
    return "serial " + port_.path() + " " + std::to_string(baud_);
  }

 private:
  SerialPort port_;
  int baud_;
};

}  // namespace aerograsp
