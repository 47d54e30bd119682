// The bus exposure check (lib/bus/bus_guard.h) on kernel tables as text.
#include "bus/bus_guard.h"

#include <gtest/gtest.h>

#include "config/config.h"

namespace evade::bus {
namespace {

constexpr uint32_t kGroup = (239u << 24) | (255u << 16) | (76u << 8) | 67u;

// /proc/net/route of a host on a LAN (default route via eth0).
const char* kLanRoutes =
    "Iface\tDestination\tGateway \tFlags\tRefCnt\tUse\tMetric\tMask\t\tMTU\tWindow\tIRTT\n"
    "eth0\t00000000\t010200C0\t0003\t0\t0\t0\t00000000\t0\t0\t0\n"
    "eth0\t000200C0\t00000000\t0001\t0\t0\t0\t00FFFFFF\t0\t0\t0\n";
// ... after tools/bus-firewall apply: the group routed to lo.
const char* kClosedRoutes =
    "Iface\tDestination\tGateway \tFlags\tRefCnt\tUse\tMetric\tMask\t\tMTU\tWindow\tIRTT\n"
    "eth0\t00000000\t010200C0\t0003\t0\t0\t0\t00000000\t0\t0\t0\n"
    "lo\t434CFFEF\t00000000\t0001\t0\t0\t0\tFFFFFFFF\t0\t0\t0\n"
    "eth0\t000200C0\t00000000\t0001\t0\t0\t0\t00FFFFFF\t0\t0\t0\n";
const char* kIgmpAllHosts =
    "Idx\tDevice    : Count Querier\tGroup    Users Timer\tReporter\n"
    "1\tlo        :     1      V3\n"
    "\t\t\t\t010000E0     1 0:00000000\t\t0\n"
    "2\teth0      :     1      V3\n"
    "\t\t\t\t010000E0     1 0:00000000\t\t0\n";
const char* kIgmpBusOnEth0 =
    "Idx\tDevice    : Count Querier\tGroup    Users Timer\tReporter\n"
    "1\tlo        :     2      V3\n"
    "\t\t\t\t434CFFEF     1 0:00000000\t\t0\n"
    "\t\t\t\t010000E0     1 0:00000000\t\t0\n"
    "2\teth0      :     2      V3\n"
    "\t\t\t\t434CFFEF     1 0:00000000\t\t0\n"
    "\t\t\t\t010000E0     1 0:00000000\t\t0\n";

TEST(BusGuard, ParsesTheDefaultUrl) {
  auto a = parse_udpm_url("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->group, kGroup);
  EXPECT_EQ(a->port, 7667);
  EXPECT_FALSE(parse_udpm_url("file:///tmp/x.lcmlog"));
  EXPECT_FALSE(parse_udpm_url("udpm://239.255.76.67:99999"));
  EXPECT_FALSE(parse_udpm_url("udpm://not-an-address:7667"));
}

TEST(BusGuard, TheMostSpecificRouteNamesTheInterface) {
  EXPECT_EQ(route_interface(kLanRoutes, kGroup).value_or(""), "eth0");
  EXPECT_EQ(route_interface(kClosedRoutes, kGroup).value_or(""), "lo");
  EXPECT_FALSE(route_interface("Iface\tDestination\n", kGroup));
}

TEST(BusGuard, IgmpMembersOfTheGroup) {
  EXPECT_TRUE(igmp_members(kIgmpAllHosts, kGroup).empty());
  EXPECT_EQ(igmp_members(kIgmpBusOnEth0, kGroup), (std::vector<std::string>{"lo", "eth0"}));
}

TEST(BusGuard, ALongInterfaceNameTouchesTheColon) {
  const char* igmp =
      "Idx\tDevice    : Count Querier\tGroup    Users Timer\tReporter\n"
      "5\tenp0s31f6veth: 1      V3\n"
      "\t\t\t\t434CFFEF     1 0:00000000\t\t0\n";
  EXPECT_EQ(igmp_members(igmp, kGroup), std::vector<std::string>{"enp0s31f6veth"});
}

TEST(BusGuard, ALanDefaultRouteExposesTheBus) {
  Exposure e = exposure(kLanRoutes, kIgmpAllHosts, kGroup, {"lo"});
  EXPECT_FALSE(e.closed());
  EXPECT_EQ(e.interfaces, std::vector<std::string>{"eth0"});
  // ... unless the LAN is the robot link
  EXPECT_TRUE(exposure(kLanRoutes, kIgmpAllHosts, kGroup, {"lo", "eth0"}).closed());
}

TEST(BusGuard, RoutedToLoIsClosedUnlessAnotherInterfaceJoinedTheGroup) {
  EXPECT_TRUE(exposure(kClosedRoutes, kIgmpAllHosts, kGroup, {"lo"}).closed());
  Exposure e = exposure(kClosedRoutes, kIgmpBusOnEth0, kGroup, {"lo"});
  EXPECT_EQ(e.interfaces, std::vector<std::string>{"eth0"});
  ASSERT_EQ(e.reasons.size(), 1u);
  EXPECT_NE(e.reasons[0].find("/proc/net/igmp"), std::string::npos);
}

// bus.auth and bus.clock_sync, which the bus: section holds beside
// allowed_interfaces (auth.h, clock_sync.h).
const std::string kAuth =
    "  auth: {key_file: /k, window_s: 2.0}\n"
    "  clock_sync: {period_s: 1.0, window_samples: 8, max_offset_s: 0.02}\n";

TEST(BusGuard, ConfigNamesTheAllowedInterfaces) {
  auto p =
      BusGuardParams::from_config(config::load_string("bus:\n  allowed_interfaces: [lo, eth1]\n" + kAuth, "t.yaml"));
  EXPECT_EQ(p.allowed_interfaces, (std::vector<std::string>{"lo", "eth1"}));
  try {
    BusGuardParams::from_config(config::load_string("bus:\n  allowed_interfaces: []\n" + kAuth, "t.yaml"));
    FAIL() << "an empty list must be refused";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml:2: key 'bus.allowed_interfaces'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      BusGuardParams::from_config(config::load_string("bus:\n  allowed_interfaces: [lo]\n  x: 1\n" + kAuth, "t")),
      config::ConfigError);
  EXPECT_NO_THROW(
      BusGuardParams::from_config(config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml")));
}

}  // namespace
}  // namespace evade::bus
