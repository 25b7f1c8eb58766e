#include "hardware/mavlink/mavlink_link.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "hardware/rgbd_camera.h"  // HardwareError

namespace aerograsp {
namespace {

bool MakeAddress(const std::string& host, int port, sockaddr_in* out) {
  std::memset(out, 0, sizeof *out);
  out->sin_family = AF_INET;
  out->sin_port = htons(static_cast<std::uint16_t>(port));
  const std::string h = host.empty() || host == "localhost" ? "127.0.0.1" : host;
  return ::inet_pton(AF_INET, h.c_str(), &out->sin_addr) == 1;
}

std::string AddressText(const sockaddr_in& a) {
  char text[INET_ADDRSTRLEN] = "?";
  ::inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(a.sin_port));
}

}  // namespace

static_assert(sizeof(sockaddr_in) <= 16, "remote_ holds a sockaddr_in");

UdpLink::UdpLink(const std::string& local_host, int local_port, const std::string& remote_host,
                 int remote_port, const std::string& device)
    : local_host_(local_host.empty() ? "0.0.0.0" : local_host) {
  const std::string where = "udp " + local_host_ + ":" + std::to_string(local_port);
  sockaddr_in local{};
  if (!MakeAddress(local_host_, local_port, &local)) {
    throw HardwareError(device + ": cannot bind " + where + ": not an IPv4 address");
  }
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
    const std::string reason = std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw HardwareError(device + ": cannot bind " + where + ": " + reason);
  }
  socklen_t size = sizeof local;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &size);
  local_port_ = ntohs(local.sin_port);
  if (remote_port > 0) {
    sockaddr_in remote{};
    if (!MakeAddress(remote_host, remote_port, &remote)) {
      ::close(fd_);
      fd_ = -1;
      throw HardwareError(device + ": udp remote " + remote_host + ": not an IPv4 address");
    }
    std::memcpy(remote_, &remote, sizeof remote);
    has_remote_ = true;
  }
}

UdpLink::~UdpLink() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpLink::Send(const std::vector<std::uint8_t>& bytes) {
  sockaddr_in remote;
  {
    std::lock_guard<std::mutex> lock(remote_mutex_);
    if (!has_remote_) return false;
    std::memcpy(&remote, remote_, sizeof remote);
  }
  return ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&remote),
                  sizeof remote) == static_cast<ssize_t>(bytes.size());
}

std::size_t UdpLink::Receive(std::uint8_t* data, std::size_t capacity, double timeout_s) {
  pollfd p{fd_, POLLIN, 0};
  const int timeout_ms = timeout_s > 0.0 ? static_cast<int>(std::ceil(timeout_s * 1000.0)) : 0;
  if (::poll(&p, 1, timeout_ms) <= 0) return 0;
  sockaddr_in from{};
  socklen_t size = sizeof from;
  const ssize_t n = ::recvfrom(fd_, data, capacity, 0, reinterpret_cast<sockaddr*>(&from), &size);
  if (n <= 0) return 0;
  std::lock_guard<std::mutex> lock(remote_mutex_);
  std::memcpy(remote_, &from, sizeof from);  // answer whoever spoke last
  has_remote_ = true;
  return static_cast<std::size_t>(n);
}

std::string UdpLink::Describe() const {
  std::string text = "udp " + local_host_ + ":" + std::to_string(local_port_);
  std::lock_guard<std::mutex> lock(remote_mutex_);
  if (has_remote_) {
    sockaddr_in remote;
    std::memcpy(&remote, remote_, sizeof remote);
    text += " -> " + AddressText(remote);
  }
  return text;
}

SerialLink::SerialLink(const std::string& path, int baud, const std::string& device)
    : port_(path, baud, device), baud_(baud) {}

}  // namespace aerograsp
