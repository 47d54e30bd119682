#include "sim/udp_sender.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace evade::sim {

UdpSender::UdpSender(const std::string& host, int port) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* res = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &res) != 0 || !res) {
    ::close(fd_);
    throw std::runtime_error("cannot resolve LiDAR destination host '" + host + "'");
  }
  std::memcpy(&dest_, res->ai_addr, sizeof(dest_));
  ::freeaddrinfo(res);
  dest_.sin_port = htons(static_cast<uint16_t>(port));
}

UdpSender::~UdpSender() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSender::send(const uint8_t* data, size_t size) {
  return ::sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&dest_), sizeof(dest_)) ==
         static_cast<ssize_t>(size);
}

LidarSenders::LidarSenders(const SimParams& p, const std::string& model)
    : host_(p.lidar_dest_host),
      model_(model),
      data_port_(p.dest_port(model, LidarPort::kData)),
      difop_port_(p.dest_port(model, LidarPort::kDifop)),
      data_(host_, data_port_),
      difop_(host_, difop_port_) {}

bool LidarSenders::send(const Packet& p) {
  return (p.port == LidarPort::kDifop ? difop_ : data_).send(p.data(), p.size());
}

std::string LidarSenders::describe() const {
  std::string s = model_ + " to " + host_ + ":" + std::to_string(data_port_);
  if (model_ != "vlp16") s += " (DIFOP :" + std::to_string(difop_port_) + ")";
  return s;
}

bool parse_host_port(const std::string& s, std::string* host, int* port) {
  size_t colon = s.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  try {
    size_t used = 0;
    int p = std::stoi(s.substr(colon + 1), &used);
    if (used != s.size() - colon - 1 || p < 1 || p > 65535) return false;
    *host = s.substr(0, colon);
    *port = p;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace evade::sim
