// A serial port in raw mode (termios, 8N1, no flow control) with timed reads:
// the transport of the servo bus (1 Mbaud) and of a MAVLink serial link. Also
// opens pseudo-terminals, where the simulated devices sit on the far end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace aerograsp {

class SerialPort {
 public:
  /// Opens `path` raw 8N1 at `baud` (a standard rate: 9600 ... 4000000).
  /// `device` names what is on the port in messages ("servo bus").
  /// @throws HardwareError "<device>: cannot open <path>: <reason>", "<device>:
  /// <path> is a regular file, not a serial port ..." (anything but a character
  /// device is refused before a byte is written) or an unsupported baud rate.
  SerialPort(const std::string& path, int baud, const std::string& device);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  const std::string& path() const { return path_; }
  /// Writes all bytes (waiting for the driver's buffer if needed). False on an I/O error.
  bool Write(const std::uint8_t* data, std::size_t size);
  /// Reads what is available, waiting up to `timeout_s` for the first byte.
  /// Returns the number of bytes read (0 on timeout or error).
  std::size_t ReadSome(std::uint8_t* data, std::size_t capacity, double timeout_s);
  /// Drops unread input (late replies of an earlier exchange).
  void DiscardInput();

 private:
  std::string path_;
  int fd_ = -1;
};

/// A pseudo-terminal pair: the master end for a simulated device, the slave
/// path for the driver under test. Both ends are raw.
class PseudoTerminal {
 public:
  /// @throws HardwareError when the system has no free pty.
  PseudoTerminal();
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  int master_fd() const { return master_fd_; }
  /// What the driver opens, e.g. "/dev/pts/7".
  const std::string& slave_path() const { return slave_path_; }

 private:
  int master_fd_ = -1;
  int slave_keepalive_fd_ = -1;  // keeps the master readable while no driver holds the slave
  std::string slave_path_;
};

/// Termios speed constant for a baud rate; 0 when unsupported.
unsigned BaudConstant(int baud);

}  // namespace aerograsp
