// The simulator's LiDAR packets on UDP: a non-blocking IPv4 sender to one
// destination, and the model's destinations (data: VLP-16 data or
// RS-Helios MSOP; RS-Helios DIFOP) on sim.lidar_dest_host. I/O adapters,
// not part of the socket-free sim core.
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/sim_core.h"

namespace evade::sim {

class UdpSender {
 public:
  // Throws std::runtime_error when the socket cannot be made or `host`
  // does not resolve.
  UdpSender(const std::string& host, int port);
  ~UdpSender();
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;
  // One datagram; false when it was not sent whole (socket full, no route).
  bool send(const uint8_t* data, size_t size);

 private:
  int fd_ = -1;
  sockaddr_in dest_{};
};

class LidarSenders {
 public:
  LidarSenders(const SimParams& p, const std::string& model);
  bool send(const Packet& p);
  // "MODEL to HOST:PORT" (and the DIFOP port), for the start-up line.
  std::string describe() const;

 private:
  std::string host_, model_;
  int data_port_, difop_port_;
  UdpSender data_, difop_;
};

// "host:port" -> (host, port) with port 1-65535; false if malformed.
bool parse_host_port(const std::string& s, std::string* host, int* port);

}  // namespace evade::sim
