#include "sensing/packet_sources.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pcap/pcap.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace evade::sensing {

namespace {
constexpr int kEtherTypeIpv4 = 0x0800;
constexpr int kEtherTypeIpv6 = 0x86DD;
constexpr int kEtherTypeVlan = 0x8100;
constexpr int kIpProtoUdp = 17;
constexpr size_t kEthernetHeader = 14;
constexpr size_t kVlanTag = 4;
constexpr size_t kLinuxCookedHeader = 16;
constexpr size_t kNullHeader = 4;
constexpr size_t kIpv6Header = 40;
constexpr size_t kUdpHeader = 8;

inline int be16(const uint8_t* p) { return (p[0] << 8) | p[1]; }
}  // namespace

PcapUdpReader::PcapUdpReader(const std::string& path) {
  char err[PCAP_ERRBUF_SIZE] = {};
  pcap_ = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_MICRO, err);
  if (!pcap_) throw std::runtime_error("cannot open capture " + path + ": " + err);
  check_link_type(path);
}

PcapUdpReader::PcapUdpReader(FILE* file, const std::string& name) {
  char err[PCAP_ERRBUF_SIZE] = {};
  pcap_ = pcap_fopen_offline_with_tstamp_precision(file, PCAP_TSTAMP_PRECISION_MICRO, err);
  if (!pcap_) {
    std::fclose(file);
    throw std::runtime_error("cannot read capture " + name + ": " + err);
  }
  check_link_type(name);
}

void PcapUdpReader::check_link_type(const std::string& name) {
  link_type_ = pcap_datalink(pcap_);
  if (link_type_ != DLT_EN10MB && link_type_ != DLT_LINUX_SLL && link_type_ != DLT_RAW && link_type_ != DLT_NULL) {
    const char* n = pcap_datalink_val_to_name(link_type_);
    pcap_close(pcap_);
    pcap_ = nullptr;
    throw std::runtime_error("capture " + name + ": unsupported link type " + (n ? n : "?"));
  }
}

PcapUdpReader::~PcapUdpReader() {
  if (pcap_) pcap_close(pcap_);
}

bool PcapUdpReader::next(UdpDatagram* out) {
  while (true) {
    pcap_pkthdr* hdr = nullptr;
    const u_char* frame = nullptr;
    int r = pcap_next_ex(pcap_, &hdr, &frame);
    if (r == PCAP_ERROR_BREAK) return false;  // end of file
    if (r != 1) {
      error_ = pcap_geterr(pcap_);
      return false;
    }
    const size_t caplen = hdr->caplen;
    size_t off = 0;
    int ethertype = kEtherTypeIpv4;
    if (link_type_ == DLT_EN10MB) {
      if (caplen < kEthernetHeader) { ++skipped_["short_frames"]; continue; }
      ethertype = be16(frame + 12);
      off = kEthernetHeader;
      if (ethertype == kEtherTypeVlan) {
        if (caplen < off + kVlanTag) { ++skipped_["short_frames"]; continue; }
        ethertype = be16(frame + off + 2);
        off += kVlanTag;
      }
    } else if (link_type_ == DLT_LINUX_SLL) {
      if (caplen < kLinuxCookedHeader) { ++skipped_["short_frames"]; continue; }
      ethertype = be16(frame + 14);
      off = kLinuxCookedHeader;
    } else if (link_type_ == DLT_NULL) {
      off = kNullHeader;
      ethertype = (caplen > off && (frame[off] >> 4) == 6) ? kEtherTypeIpv6 : kEtherTypeIpv4;
    } else {  // raw IP: the version nibble tells
      ethertype = (caplen > 0 && (frame[0] >> 4) == 6) ? kEtherTypeIpv6 : kEtherTypeIpv4;
    }
    size_t udp = 0;
    if (ethertype == kEtherTypeIpv4) {
      if (caplen < off + 20 || (frame[off] >> 4) != 4) { ++skipped_["not_ip"]; continue; }
      const size_t ihl = static_cast<size_t>(frame[off] & 0x0F) * 4;
      const int frag = be16(frame + off + 6);
      if ((frag & 0x2000) || (frag & 0x1FFF)) { ++skipped_["ip_fragments"]; continue; }
      if (frame[off + 9] != kIpProtoUdp) { ++skipped_["not_udp"]; continue; }
      udp = off + ihl;
    } else if (ethertype == kEtherTypeIpv6) {
      if (caplen < off + kIpv6Header) { ++skipped_["not_ip"]; continue; }
      if (frame[off + 6] != kIpProtoUdp) { ++skipped_["not_udp"]; continue; }
      udp = off + kIpv6Header;
    } else {
      ++skipped_["not_ip"];
      continue;
    }
    if (caplen < udp + kUdpHeader) { ++skipped_["short_frames"]; continue; }
    const int udp_len = be16(frame + udp + 4);
    if (udp_len < static_cast<int>(kUdpHeader)) { ++skipped_["bad_udp_length"]; continue; }
    const size_t want = static_cast<size_t>(udp_len) - kUdpHeader;
    const size_t have = caplen - (udp + kUdpHeader);
    out->utime = static_cast<int64_t>(hdr->ts.tv_sec) * 1'000'000 + hdr->ts.tv_usec;
    out->dst_port = be16(frame + udp + 2);
    out->truncated = have < want;
    const size_t n = out->truncated ? have : want;
    out->payload.assign(frame + udp + kUdpHeader, frame + udp + kUdpHeader + n);
    return true;
  }
}

int open_udp_socket(const std::string& address, int port, int receive_buffer_bytes) {
  int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  // No SO_REUSEADDR: a second driver on the same port must fail loudly
  // rather than silently share (or steal) the sensor's unicast packets.
  // Broadcast packets (a Velodyne's default destination) reach a socket
  // bound to 0.0.0.0 without any option.
  int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &one, sizeof(one));
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, address.c_str(), &sa.sin_addr) != 1) {
    ::close(fd);
    throw std::runtime_error("bad bind address " + address);
  }
  if (::bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof(sa)) != 0) {
    int e = errno;
    ::close(fd);
    throw std::runtime_error("cannot bind UDP " + address + ":" + std::to_string(port) + ": " + std::strerror(e));
  }
  return fd;
}

bool receive_datagram(int fd, std::vector<uint8_t>& buffer, UdpDatagram* out, int64_t fallback_utime) {
  iovec iov{buffer.data(), buffer.size()};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval))];
  sockaddr_in from{};
  msghdr msg{};
  msg.msg_name = &from;
  msg.msg_namelen = sizeof(from);
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof(control);
  ssize_t n = ::recvmsg(fd, &msg, MSG_DONTWAIT);
  if (n < 0) return false;
  out->utime = fallback_utime;
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
      timeval tv;
      std::memcpy(&tv, CMSG_DATA(c), sizeof(tv));
      out->utime = static_cast<int64_t>(tv.tv_sec) * 1'000'000 + tv.tv_usec;
    }
  }
  out->truncated = (msg.msg_flags & MSG_TRUNC) != 0;
  out->dst_port = 0;
  out->payload.assign(buffer.data(), buffer.data() + n);
  return true;
}

}  // namespace evade::sensing
