// Is the LCM bus closed to the networks it should not hear?
//
// LCM 1.3.1's receive socket joins the bus group on whichever interface the
// kernel's route for the group names, and with IP_MULTICAST_ALL (Linux's
// default) every socket bound to the bus port receives what arrives for
// any group membership on the host. So the bus is open to an interface
// when the route for the group leaves through it, or when that interface
// has joined the group (/proc/net/igmp). ttl=0 only limits what is sent.
//
// This module reads those two kernel tables, never a socket: it sends
// nothing. The closure itself is the host's setup (tools/bus-firewall:
// the group routed to an allowed interface, plus a firewall rule where nft
// exists); this is the check every process runs at start (warn_if_exposed).
// It does not read firewall state (that needs CAP_NET_ADMIN):
// `tools/bus-firewall check` reports it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bus/auth.h"
#include "bus/clock_sync.h"
#include "config/config.h"
#include "config/fields.h"

namespace evade::bus {

// The `bus:` section of the robot configuration.
struct BusGuardParams {
  // Interfaces that may carry the bus: lo on one host, plus the robot
  // link's interface when the stack spans two hosts.
  std::vector<std::string> allowed_interfaces{"lo"};
  AuthParams auth;             // bus.auth (auth.h)
  ClockSyncParams clock_sync;  // bus.clock_sync (clock_sync.h)

  template <class V>
  void fields(V& v) {
    v.field("allowed_interfaces", allowed_interfaces);
    for (const auto& name : allowed_interfaces)
      v.rule(name.size() <= 15 && name.find_first_of(" /\t:") == std::string::npos, "allowed_interfaces",
             "'" + name + "' is not an interface name");
    v.section("auth", auth);
    v.section("clock_sync", clock_sync);
  }
  // root = the whole configuration; reads `bus:`.
  static BusGuardParams from_config(const config::Node& root);
};

struct BusAddress {
  uint32_t group = 0;  // host byte order
  int port = 0;
};
// The group and port of a udpm:// URL; nullopt for another provider or a
// malformed URL.
std::optional<BusAddress> parse_udpm_url(const std::string& url);

// The interface of the most specific route to `group` in /proc/net/route
// text (the main table; lowest metric among equals); nullopt if none.
std::optional<std::string> route_interface(const std::string& proc_net_route, uint32_t group);
// Interfaces that have joined `group`, from /proc/net/igmp text.
std::vector<std::string> igmp_members(const std::string& proc_net_igmp, uint32_t group);

struct Exposure {
  std::vector<std::string> interfaces;  // not allowed, yet the bus is reachable through them
  std::vector<std::string> reasons;     // one line each, for the warning
  bool closed() const { return interfaces.empty(); }
};
Exposure exposure(const std::string& proc_net_route, const std::string& proc_net_igmp, uint32_t group,
                  const std::vector<std::string>& allowed);
// The same on this host's /proc/net/{route,igmp}. A non-udpm URL is closed.
Exposure host_exposure(const std::string& url, const std::vector<std::string>& allowed);

// At a live process's start: on exposure, one line on stderr
// ("<process>: warning: the LCM bus ... is reachable from eth0 ...") and
// the number of exposed interfaces returned (for HEALTH's
// bus_exposed_interfaces counter); 0 when closed.
int64_t warn_if_exposed(const std::string& process, const std::string& url, const BusGuardParams& params);

}  // namespace evade::bus
