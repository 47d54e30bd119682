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

// A frame read so far: where the next header starts and what it is.
struct FrameCursor {
  const uint8_t* frame;
  size_t caplen;
  size_t off = 0;
  int ethertype = kEtherTypeIpv4;
};

// Skips the link-layer header of link_type; returns the reason to skip the
// frame (a key of PcapUdpReader::skipped()), or nullptr.
const char* skip_link_header(int link_type, FrameCursor& f) {
  if (link_type == DLT_EN10MB) {
    if (f.caplen < kEthernetHeader) return "short_frames";
    f.ethertype = be16(f.frame + 12);
    f.off = kEthernetHeader;
    if (f.ethertype == kEtherTypeVlan) {
      if (f.caplen < f.off + kVlanTag) return "short_frames";
      f.ethertype = be16(f.frame + f.off + 2);
      f.off += kVlanTag;
    }
  } else if (link_type == DLT_LINUX_SLL) {
    if (f.caplen < kLinuxCookedHeader) return "short_frames";
    f.ethertype = be16(f.frame + 14);
    f.off = kLinuxCookedHeader;
  } else if (link_type == DLT_NULL) {
    f.off = kNullHeader;
    f.ethertype = (f.caplen > f.off && (f.frame[f.off] >> 4) == 6) ? kEtherTypeIpv6 : kEtherTypeIpv4;
  } else {  // raw IP: the version nibble tells
    f.ethertype = (f.caplen > 0 && (f.frame[0] >> 4) == 6) ? kEtherTypeIpv6 : kEtherTypeIpv4;
  }
  return nullptr;
}

// Skips the IPv4 or IPv6 header up to the UDP header (unfragmented UDP
// only); returns the reason to skip the frame, or nullptr.
const char* skip_ip_header(FrameCursor& f) {
  auto ip = [&f](size_t i) { return f.frame[f.off + i]; };  // read after the length checks
  if (f.ethertype == kEtherTypeIpv4) {
    if (f.caplen < f.off + 20 || (ip(0) >> 4) != 4) return "not_ip";
    const size_t ihl = static_cast<size_t>(ip(0) & 0x0F) * 4;
    const int frag = (ip(6) << 8 | ip(7));
    if ((frag & 0x2000) || (frag & 0x1FFF)) return "ip_fragments";
    if (ip(9) != kIpProtoUdp) return "not_udp";
    f.off += ihl;
  } else if (f.ethertype == kEtherTypeIpv6) {
    if (f.caplen < f.off + kIpv6Header) return "not_ip";
    if (ip(6) != kIpProtoUdp) return "not_udp";
    f.off += kIpv6Header;
  } else {
    return "not_ip";
  }
  return nullptr;
}

// The UDP datagram at f.off (payload cut at the capture length: truncated);
// returns the reason to skip the frame, or nullptr.
const char* read_udp(const FrameCursor& f, UdpDatagram* out) {
  const size_t udp = f.off;
  if (f.caplen < udp + kUdpHeader) return "short_frames";
  const int udp_len = be16(f.frame + udp + 4);
  if (udp_len < static_cast<int>(kUdpHeader)) return "bad_udp_length";
  const size_t want = static_cast<size_t>(udp_len) - kUdpHeader;
  const size_t have = f.caplen - (udp + kUdpHeader);
  out->dst_port = be16(f.frame + udp + 2);
  out->truncated = have < want;
  const size_t n = out->truncated ? have : want;
  out->payload.assign(f.frame + udp + kUdpHeader, f.frame + udp + kUdpHeader + n);
  return nullptr;
}
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
    FrameCursor f{frame, hdr->caplen};
    const char* skip = skip_link_header(link_type_, f);
    if (!skip) skip = skip_ip_header(f);
    if (!skip) skip = read_udp(f, out);
    if (skip) {
      ++skipped_[skip];
      continue;
    }
    out->utime = static_cast<int64_t>(hdr->ts.tv_sec) * 1'000'000 + hdr->ts.tv_usec;
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

PcapUdpWriter::PcapUdpWriter(const std::string& path, const std::string& src_ip, const std::string& dst_ip) {
  in_addr a{}, b{};
  if (inet_pton(AF_INET, src_ip.c_str(), &a) != 1) throw std::runtime_error("not an IPv4 address: " + src_ip);
  if (inet_pton(AF_INET, dst_ip.c_str(), &b) != 1) throw std::runtime_error("not an IPv4 address: " + dst_ip);
  src_ip_ = a.s_addr;
  dst_ip_ = b.s_addr;
  pcap_ = pcap_open_dead_with_tstamp_precision(DLT_EN10MB, 65535, PCAP_TSTAMP_PRECISION_MICRO);
  if (!pcap_) throw std::runtime_error("pcap_open_dead failed");
  dumper_ = pcap_dump_open(pcap_, path.c_str());
  if (!dumper_) {
    std::string why = pcap_geterr(pcap_);
    pcap_close(pcap_);
    pcap_ = nullptr;
    throw std::runtime_error("cannot write capture " + path + ": " + why);
  }
}

PcapUdpWriter::~PcapUdpWriter() { close(); }

void PcapUdpWriter::close() {
  if (dumper_) pcap_dump_close(dumper_);
  if (pcap_) pcap_close(pcap_);
  dumper_ = nullptr;
  pcap_ = nullptr;
}

void PcapUdpWriter::write(int64_t utime, int src_port, int dst_port, const uint8_t* payload, size_t size) {
  if (!dumper_) throw std::runtime_error("capture already closed");
  constexpr size_t kIpv4Header = 20;
  if (size > 65535 - kIpv4Header - kUdpHeader) throw std::runtime_error("datagram too large for one IPv4 packet");
  std::vector<uint8_t> f(kEthernetHeader + kIpv4Header + kUdpHeader + size, 0);
  auto put16 = [&](size_t at, unsigned v) {
    f[at] = static_cast<uint8_t>(v >> 8);
    f[at + 1] = static_cast<uint8_t>(v & 0xFF);
  };
  // Ethernet: locally administered MACs, IPv4.
  const uint8_t dst_mac[6] = {0x02, 0, 0, 0, 0, 0x02}, src_mac[6] = {0x02, 0, 0, 0, 0, 0x01};
  std::memcpy(&f[0], dst_mac, 6);
  std::memcpy(&f[6], src_mac, 6);
  put16(12, kEtherTypeIpv4);
  uint8_t* ip = &f[kEthernetHeader];
  ip[0] = 0x45;
  put16(kEthernetHeader + 2, static_cast<unsigned>(kIpv4Header + kUdpHeader + size));
  put16(kEthernetHeader + 4, ip_id_++);
  put16(kEthernetHeader + 6, 0x4000);  // don't fragment
  ip[8] = 64;
  ip[9] = kIpProtoUdp;
  std::memcpy(ip + 12, &src_ip_, 4);
  std::memcpy(ip + 16, &dst_ip_, 4);
  uint32_t sum = 0;
  for (size_t i = 0; i < kIpv4Header; i += 2) sum += static_cast<uint32_t>((ip[i] << 8) | ip[i + 1]);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  put16(kEthernetHeader + 10, ~sum & 0xFFFF);
  const size_t udp = kEthernetHeader + kIpv4Header;
  put16(udp, static_cast<unsigned>(src_port));
  put16(udp + 2, static_cast<unsigned>(dst_port));
  put16(udp + 4, static_cast<unsigned>(kUdpHeader + size));  // checksum 0: not computed (allowed in IPv4)
  std::memcpy(&f[udp + kUdpHeader], payload, size);
  pcap_pkthdr hdr{};
  hdr.ts.tv_sec = static_cast<time_t>(utime / 1'000'000);
  hdr.ts.tv_usec = static_cast<suseconds_t>(utime % 1'000'000);
  hdr.caplen = hdr.len = static_cast<bpf_u_int32>(f.size());
  pcap_dump(reinterpret_cast<u_char*>(dumper_), &hdr, f.data());
}

}  // namespace evade::sensing
