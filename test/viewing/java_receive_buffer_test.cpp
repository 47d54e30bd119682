// tools/lcm-spy's receive buffer fix (tools/src/lcm-java), headless, inside
// a private network namespace (NETNS): Java's LCM with the fix applied hears
// every 30,000-point cloud published at 10 Hz.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

#include "evade/pointcloud_t.hpp"

namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608";

struct ProbeResult {
  int messages = -1;
  int bytes = -1;
  int granted = -1;
};

// Runs a Java counter (evade.tools.Probe, or lcm-spy itself through
// evade.tools.SpyRate under xvfb-run) while publishing `count` clouds at 10 Hz.
ProbeResult probe_while_publishing(bool fix, int count, bool spy = false) {
  const std::string java = std::string("java -Djava.net.preferIPv4Stack=true -cp /usr/share/java/lcm.jar:") +
                           EVADE_TOOLS_JAR + ":" + EVADE_TYPES_JAR + ":/usr/share/java/jchart2d.jar";
  const std::string args =
      std::string(" '") + kUrl + "' CLOUD " + std::to_string(count * 0.1 + 2.0) + (fix ? " 1" : " 0");
  const std::string cmd =
      spy ? "xvfb-run -a -s '-screen 0 1024x768x24' " + java + " evade.tools.SpyRate" + args + " 2>/dev/null"
          : java + " evade.tools.Probe" + args;
  FILE* p = ::popen(cmd.c_str(), "r");
  EXPECT_NE(p, nullptr);
  char line[256] = {0};
  bool ready = false;  // "ready": subscribed (lcm-spy prints its class scan before)
  while (!ready && std::fgets(line, sizeof line, p)) ready = std::string(line) == "ready\n";
  EXPECT_TRUE(ready);

  lcm::LCM lcm(kUrl);
  EXPECT_TRUE(lcm.good());
  evade::pointcloud_t c{};
  c.sensor_model = "vlp16";
  c.n = 30000;
  c.x.assign(c.n, 1.0f);
  c.y.assign(c.n, 2.0f);
  c.z.assign(c.n, 3.0f);
  c.intensity.assign(c.n, 4.0f);
  c.ring.assign(c.n, 1);
  c.time_offset.assign(c.n, 7);
  for (int i = 0; i < count; ++i) {
    c.utime = i;
    lcm.publish("CLOUD", &c);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ProbeResult r;
  EXPECT_NE(std::fgets(line, sizeof line, p), nullptr);
  if (spy) {
    EXPECT_EQ(std::sscanf(line, "%d", &r.messages), 1) << line;
  } else {
    EXPECT_EQ(std::sscanf(line, "%d %d %d", &r.messages, &r.bytes, &r.granted), 3) << line;
  }
  ::pclose(p);
  return r;
}

TEST(LcmSpyReceiveBuffer, JavaLcmWithTheFixHearsEveryCloud) {
  const int n = 30;
  const ProbeResult without = probe_while_publishing(false, n);
  const ProbeResult with = probe_while_publishing(true, n);
  std::printf(
      "Java LCM, 30 clouds of 30,000 points at 10 Hz: %d heard without the fix, %d with "
      "(buffer granted %d bytes)\n",
      without.messages, with.messages, with.granted);
  EXPECT_EQ(with.messages, n);
  EXPECT_GT(with.granted, 1 << 20);
  EXPECT_GE(with.bytes, 30000 * 21);  // x, y, z, intensity, ring, time_offset: the whole cloud arrived
}

// lcm-spy's own channel table, as tools/lcm-spy starts it.
TEST(LcmSpyReceiveBuffer, LcmSpyCountsEveryCloudWithTheFix) {
  const int n = 30;
  const ProbeResult without = probe_while_publishing(false, n, true);
  const ProbeResult with = probe_while_publishing(true, n, true);
  std::printf("lcm-spy, 30 clouds of 30,000 points at 10 Hz: %d counted without the fix, %d with\n", without.messages,
              with.messages);
  EXPECT_EQ(with.messages, n);
}

}  // namespace
