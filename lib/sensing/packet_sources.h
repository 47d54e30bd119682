// Where LiDAR packets come from: a libpcap capture file or a UDP socket.
// Both hand the lidar_driver core the same thing, a UDP payload and the
// time it was received.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

typedef struct pcap pcap_t;
typedef struct pcap_dumper pcap_dumper_t;

namespace evade::sensing {

struct UdpDatagram {
  int64_t utime = 0;  // us: capture time (pcap) or kernel receive time (socket)
  int dst_port = 0;
  bool truncated = false;  // the capture holds fewer bytes than the UDP length
  std::vector<uint8_t> payload;
};

// Reads the UDP datagrams of a capture (Ethernet, Linux cooked or raw IP
// link types; IPv4 and IPv6). Frames that are not UDP, and IP fragments,
// are skipped and counted in `skipped()`.
class PcapUdpReader {
 public:
  explicit PcapUdpReader(const std::string& path);  // throws std::runtime_error
  // Reads an already open capture stream (e.g. fmemopen); takes the FILE.
  PcapUdpReader(FILE* file, const std::string& name);  // throws std::runtime_error
  ~PcapUdpReader();
  PcapUdpReader(const PcapUdpReader&) = delete;
  PcapUdpReader& operator=(const PcapUdpReader&) = delete;

  // false at end of file (or on a read error, see error()).
  bool next(UdpDatagram* out);
  const std::map<std::string, int64_t>& skipped() const { return skipped_; }
  const std::string& error() const { return error_; }

 private:
  void check_link_type(const std::string& name);
  pcap_t* pcap_ = nullptr;
  int link_type_ = 0;
  std::map<std::string, int64_t> skipped_;
  std::string error_;
};

// Writes UDP datagrams into a libpcap capture (Ethernet, IPv4, microsecond
// time stamps), as a sensor's traffic would be recorded: for synthetic
// captures (build/bin/sim-pcap) and tests. Throws std::runtime_error.
class PcapUdpWriter {
 public:
  // Datagrams go from src (the sensor) to dst (the host); addresses in
  // dotted IPv4.
  PcapUdpWriter(const std::string& path, const std::string& src_ip, const std::string& dst_ip);
  ~PcapUdpWriter();
  PcapUdpWriter(const PcapUdpWriter&) = delete;
  PcapUdpWriter& operator=(const PcapUdpWriter&) = delete;
  void write(int64_t utime, int src_port, int dst_port, const uint8_t* payload, size_t size);
  void close();  // flushes; the destructor closes too

 private:
  pcap_t* pcap_ = nullptr;
  pcap_dumper_t* dumper_ = nullptr;
  uint32_t src_ip_ = 0, dst_ip_ = 0;  // network order
  uint16_t ip_id_ = 0;
};

// A non-blocking UDP socket bound to address:port with the kernel's
// receive timestamps on. Throws std::runtime_error with the reason.
int open_udp_socket(const std::string& address, int port, int receive_buffer_bytes);
// Reads one datagram if one is waiting (false otherwise). `buffer` must be
// able to hold any datagram (64 KiB); payload holds the datagram's bytes.
bool receive_datagram(int fd, std::vector<uint8_t>& buffer, UdpDatagram* out, int64_t fallback_utime);

}  // namespace evade::sensing
