#include "netem/impairment.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "netem/lcm_packet.h"

namespace evade::netem {
namespace {

void put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<uint8_t>(v >> s));
}
void put16(std::vector<uint8_t>& b, uint16_t v) {
  b.push_back(static_cast<uint8_t>(v >> 8));
  b.push_back(static_cast<uint8_t>(v));
}

// An IPv4 + UDP packet from `port` holding an LCM short message, or fragment
// `frag` of `nfrag` (the channel in fragment 0 only).
std::vector<uint8_t> packet(uint16_t port, uint32_t seqno, const std::string& channel, int frag = -1, int nfrag = 0) {
  std::vector<uint8_t> b(20, 0);
  b[0] = 0x45;
  b[9] = 17;
  put16(b, port);
  put16(b, 7667);
  put32(b, 0);  // length, checksum: not read
  put32(b, frag < 0 ? 0x4c433032 : 0x4c433033);
  put32(b, seqno);
  if (frag >= 0) {
    put32(b, 1000);
    put32(b, 100 * frag);
    put16(b, static_cast<uint16_t>(frag));
    put16(b, static_cast<uint16_t>(nfrag));
  }
  if (frag <= 0) {
    b.insert(b.end(), channel.begin(), channel.end());
    b.push_back(0);
  }
  b.resize(b.size() + 16, 0xab);
  return b;
}

Verdict feed(Impairment& imp, const std::vector<uint8_t>& p, double t) { return imp.on_packet(p.data(), p.size(), t); }

TEST(LcmPacket, ShortMessagesAndFragmentsAreRecognised) {
  auto s = packet(4000, 7, "ODOMETRY");
  auto p = parse_lcm_packet(s.data(), s.size());
  ASSERT_TRUE(p);
  EXPECT_EQ(p->channel, "ODOMETRY");
  EXPECT_EQ(p->seqno, 7u);
  EXPECT_EQ(p->src_port, 4000);
  EXPECT_FALSE(p->fragmented);
  auto f1 = packet(4000, 8, "", 1, 3);
  p = parse_lcm_packet(f1.data(), f1.size());
  ASSERT_TRUE(p);
  EXPECT_TRUE(p->fragmented);
  EXPECT_EQ(p->fragment, 1);
  EXPECT_EQ(p->fragments, 3);
  EXPECT_EQ(p->channel, "");
  auto bad = s;
  bad[9] = 6;  // TCP
  EXPECT_FALSE(parse_lcm_packet(bad.data(), bad.size()));
  EXPECT_FALSE(parse_lcm_packet(s.data(), 30));
  auto bad_frag = packet(4000, 8, "", 3, 3);  // fragment 3 of 3
  EXPECT_FALSE(parse_lcm_packet(bad_frag.data(), bad_frag.size()));
}

TEST(Impairment, LossAndDelayFollowTheParameters) {
  Impairment imp({0.05, 0.020, 0.020, 3, {}});
  int dropped = 0, n = 20000;
  double dmin = 1, dmax = 0, sum = 0;
  for (int i = 0; i < n; ++i) {
    const double t = i * 0.001;
    auto v = feed(imp, packet(4000, i, "ODOMETRY"), t);
    if (v.drop) {
      ++dropped;
      continue;
    }
    const double d = v.release_s - t;
    dmin = std::min(dmin, d), dmax = std::max(dmax, d), sum += d;
  }
  EXPECT_NEAR(dropped / double(n), 0.05, 0.006);
  EXPECT_GE(dmin, 0.0);
  EXPECT_LT(dmin, 0.001);
  EXPECT_LE(dmax, 0.040);
  EXPECT_GT(dmax, 0.039);
  EXPECT_NEAR(sum / (n - dropped), 0.020, 0.001);
  const auto& s = imp.stats().at("ODOMETRY");
  EXPECT_EQ(s.packets, n);
  EXPECT_EQ(s.packets_dropped, dropped);
  EXPECT_EQ(s.messages_lost, dropped);
}

TEST(Impairment, AMessageIsLostOnceWhenAnyOfItsFragmentsIsAndFragmentsKeepItsChannel) {
  Impairment all_lost({1.0, 0.0, 0.0, 1, {}});
  for (int f = 0; f < 4; ++f) EXPECT_TRUE(feed(all_lost, packet(4000, 9, "LIDAR_POINTS", f, 4), 0.0).drop);
  const auto& s = all_lost.stats().at("LIDAR_POINTS");
  EXPECT_EQ(s.packets, 4);
  EXPECT_EQ(s.messages, 1);
  EXPECT_EQ(s.messages_lost, 1);
  Impairment none({0.0, 0.0, 0.0, 1, {}});
  for (int f = 0; f < 4; ++f) EXPECT_FALSE(feed(none, packet(4000, 9, "LIDAR_POINTS", f, 4), 0.0).drop);
  EXPECT_EQ(none.stats().at("LIDAR_POINTS").messages_lost, 0);
  EXPECT_EQ(none.stats().count("(fragment of an unseen message)"), 0u);
}

TEST(Impairment, ExemptChannelsPassAtOnce) {
  Impairment imp({1.0, 0.02, 0.02, 1, {"SIM_TRUTH"}});
  auto v = feed(imp, packet(4000, 1, "SIM_TRUTH"), 5.0);
  EXPECT_FALSE(v.drop);
  EXPECT_DOUBLE_EQ(v.release_s, 5.0);
  EXPECT_TRUE(feed(imp, packet(4000, 2, "CMD_VEL"), 5.0).drop);
}

TEST(Impairment, JitterReordersUnlessToldNotTo) {
  for (bool reorder : {true, false}) {
    ImpairmentParams p{0.0, 0.020, 0.020, 5, {}};
    p.reorder = reorder;
    Impairment imp(p);
    int overtaken = 0;
    double last = 0;
    for (int i = 0; i < 1000; ++i) {
      auto v = feed(imp, packet(4000, i, "CMD_VEL"), i * 0.002);
      if (v.release_s < last) ++overtaken;
      last = std::max(last, v.release_s);
    }
    if (reorder)
      EXPECT_GT(overtaken, 100);
    else
      EXPECT_EQ(overtaken, 0);
  }
  EXPECT_THROW(Impairment({1.5, 0, 0, 1, {}}), std::invalid_argument);
  EXPECT_THROW(Impairment({0.1, -1, 0, 1, {}}), std::invalid_argument);
}

}  // namespace
}  // namespace evade::netem
