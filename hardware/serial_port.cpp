#include "hardware/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "hardware/rgbd_camera.h"  // HardwareError

namespace aerograsp {
namespace {

void MakeRaw(int fd, unsigned speed) {
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) return;  // a character device that is no tty: nothing to set
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | CRTSCTS | PARENB);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (speed != 0) {
    cfsetispeed(&tio, speed);
    cfsetospeed(&tio, speed);
  }
  tcsetattr(fd, TCSANOW, &tio);
}

const char* FileKind(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a pipe";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISBLK(mode)) return "a block device";
  return "not a character device";
}

int PollTimeoutMs(double timeout_s) {
  if (!(timeout_s > 0.0)) return 0;
  return static_cast<int>(std::ceil(timeout_s * 1000.0));
}

}  // namespace

unsigned BaudConstant(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 500000:
      return B500000;
    case 921600:
      return B921600;
    case 1000000:
      return B1000000;
    case 1500000:
      return B1500000;
    case 2000000:
      return B2000000;
    case 3000000:
      return B3000000;
    case 4000000:
      return B4000000;
    default:
      return 0;
  }
}

SerialPort::SerialPort(const std::string& path, int baud, const std::string& device) : path_(path) {
  const unsigned speed = BaudConstant(baud);
  if (speed == 0) {
    throw HardwareError(device + ": " + path + ": unsupported baud rate " + std::to_string(baud));
  }
  // Only a character device (a serial adapter, a pty) is a port: a typo naming
  // a regular file or a folder must not receive a single byte.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw HardwareError(device + ": cannot open " + path + ": " + std::strerror(errno));
  }
  if (!S_ISCHR(st.st_mode)) {
    throw HardwareError(device + ": " + path + " is " + FileKind(st.st_mode) +
                        ", not a serial port (a character device such as /dev/ttyUSB0)");
  }
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    throw HardwareError(device + ": cannot open " + path + ": " + std::strerror(errno));
  }
  if (::fstat(fd_, &st) != 0 || !S_ISCHR(st.st_mode)) {  // replaced since the stat
    ::close(fd_);
    fd_ = -1;
    throw HardwareError(device + ": " + path + " is not a serial port (a character device)");
  }
  MakeRaw(fd_, speed);
  tcflush(fd_, TCIOFLUSH);
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

bool SerialPort::Write(const std::uint8_t* data, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
    } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 100) <= 0) return false;
    } else {
      return false;
    }
  }
  return true;
}

std::size_t SerialPort::ReadSome(std::uint8_t* data, std::size_t capacity, double timeout_s) {
  pollfd p{fd_, POLLIN, 0};
  int ready;
  do {
    ready = ::poll(&p, 1, PollTimeoutMs(timeout_s));
  } while (ready < 0 && errno == EINTR);
  if (ready <= 0 || !(p.revents & POLLIN)) return 0;
  const ssize_t n = ::read(fd_, data, capacity);
  return n > 0 ? static_cast<std::size_t>(n) : 0;
}

void SerialPort::DiscardInput() {
  std::uint8_t scratch[256];
  while (::read(fd_, scratch, sizeof scratch) > 0) {
  }
}

PseudoTerminal::PseudoTerminal() {
  master_fd_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_fd_ < 0 || ::grantpt(master_fd_) != 0 || ::unlockpt(master_fd_) != 0) {
    throw HardwareError(std::string("pseudo-terminal: cannot open one: ") + std::strerror(errno));
  }
  char name[128];
  if (::ptsname_r(master_fd_, name, sizeof name) != 0) {
    throw HardwareError(std::string("pseudo-terminal: no slave name: ") + std::strerror(errno));
  }
  slave_path_ = name;
  slave_keepalive_fd_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_keepalive_fd_ >= 0) MakeRaw(slave_keepalive_fd_, B1000000);
  MakeRaw(master_fd_, 0);
  ::fcntl(master_fd_, F_SETFL, ::fcntl(master_fd_, F_GETFL) | O_NONBLOCK);
}

PseudoTerminal::~PseudoTerminal() {
  if (slave_keepalive_fd_ >= 0) ::close(slave_keepalive_fd_);
  if (master_fd_ >= 0) ::close(master_fd_);
}

}  // namespace aerograsp
