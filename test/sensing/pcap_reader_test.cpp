// PcapUdpReader on the small hand-made captures of the fuzz corpus
// (test/fuzz/corpus/make_lidar_seeds.py): link types, VLAN, IPv6, fragments,
// truncated records.
#include <gtest/gtest.h>

#include <cstdio>

#include "sensing/packet_sources.h"

namespace evade::sensing {
namespace {

std::string corpus(const std::string& name) {
  return std::string(EVADE_SOURCE_DIR) + "/test/fuzz/corpus/lidar_pcap/" + name;
}

std::vector<UdpDatagram> read_all(PcapUdpReader& r) {
  std::vector<UdpDatagram> out;
  UdpDatagram d;
  while (r.next(&d)) out.push_back(d);
  EXPECT_TRUE(r.error().empty()) << r.error();
  return out;
}

TEST(PcapUdpReader, EthernetVlanFragmentAndTruncatedRecords) {
  PcapUdpReader r(corpus("vlan_fragment_truncated.pcap"));
  auto d = read_all(r);
  ASSERT_EQ(d.size(), 3u);  // the IP fragment is skipped
  EXPECT_EQ(d[0].dst_port, 2368);
  EXPECT_EQ(d[0].payload.size(), 1206u);
  EXPECT_FALSE(d[0].truncated);
  EXPECT_EQ(d[0].utime, 1'700'000'000'000'000LL);
  EXPECT_EQ(d[1].dst_port, 2368);
  EXPECT_TRUE(d[1].truncated);  // 600 bytes of a 1234-byte frame captured
  EXPECT_LT(d[1].payload.size(), 1206u);
  EXPECT_EQ(d[2].dst_port, 8308);
  EXPECT_EQ(d[2].payload.size(), 512u);
  EXPECT_EQ(r.skipped().at("ip_fragments"), 1);
}

TEST(PcapUdpReader, LinuxCookedIpv6AndRawIp) {
  for (const char* name : {"linux_cooked_ipv6.pcap", "raw_ip.pcap"}) {
    PcapUdpReader r(corpus(name));
    auto d = read_all(r);
    ASSERT_EQ(d.size(), 3u) << name;
    for (size_t i = 0; i < d.size(); ++i) {
      EXPECT_EQ(d[i].payload.size(), 1206u);
      EXPECT_EQ(d[i].payload[0], 0xFF);
      EXPECT_EQ(d[i].payload[1], 0xEE);
      EXPECT_EQ(d[i].utime, 1'700'000'000'000'000LL + 1327 * static_cast<int64_t>(i));
    }
  }
}

TEST(PcapUdpReader, RejectsWhatIsNotACapture) {
  EXPECT_THROW(PcapUdpReader("/nonexistent/file.pcap"), std::runtime_error);
  static char junk[] = "definitely not a pcap file header....";
  FILE* f = fmemopen(junk, sizeof(junk), "rb");
  EXPECT_THROW(PcapUdpReader(f, "junk"), std::runtime_error);
}

}  // namespace
}  // namespace evade::sensing
