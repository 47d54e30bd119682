#include "bus/bus_guard.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace evade::bus {
namespace {

// /proc/net/{route,igmp} print a network-order address as a host integer.
bool parse_proc_address(const std::string& hex, uint32_t* out) {
  if (hex.empty() || hex.size() > 8) return false;
  uint32_t v = 0;
  for (char c : hex) {
    int d;
    if (c >= '0' && c <= '9')
      d = c - '0';
    else if (c >= 'a' && c <= 'f')
      d = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F')
      d = c - 'A' + 10;
    else
      return false;
    v = (v << 4) | static_cast<uint32_t>(d);
  }
  *out = ntohl(v);
  return true;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string dotted(uint32_t a) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%u.%u.%u.%u", a >> 24, (a >> 16) & 255, (a >> 8) & 255, a & 255);
  return buf;
}

}  // namespace

BusGuardParams BusGuardParams::from_config(const config::Node& root) {
  return config::load<BusGuardParams>(root.section("bus"));
}

std::optional<BusAddress> parse_udpm_url(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0) return std::nullopt;
  std::string rest = url.substr(scheme.size());
  rest = rest.substr(0, rest.find('?'));
  BusAddress a;
  a.port = 7667;  // LCM's default
  const size_t colon = rest.find(':');
  const std::string host = rest.substr(0, colon);
  if (colon != std::string::npos) {
    const std::string port = rest.substr(colon + 1);
    if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
      return std::nullopt;
    a.port = std::stoi(port);
    if (a.port < 1 || a.port > 65535) return std::nullopt;
  }
  in_addr addr{};
  if (host.empty()) {
    a.group = (239u << 24) | (255u << 16) | (76u << 8) | 67u;  // LCM's default group
  } else if (inet_pton(AF_INET, host.c_str(), &addr) == 1) {
    a.group = ntohl(addr.s_addr);
  } else {
    return std::nullopt;
  }
  return a;
}

std::optional<std::string> route_interface(const std::string& proc_net_route, uint32_t group) {
  std::istringstream in(proc_net_route);
  std::string line;
  std::getline(in, line);  // header
  std::optional<std::string> best;
  int best_prefix = -1;
  long best_metric = std::numeric_limits<long>::max();
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string iface, dest, gw, flags, refcnt, use, metric, mask;
    if (!(f >> iface >> dest >> gw >> flags >> refcnt >> use >> metric >> mask)) continue;
    uint32_t d, m;
    if (!parse_proc_address(dest, &d) || !parse_proc_address(mask, &m)) continue;
    unsigned long fl = std::strtoul(flags.c_str(), nullptr, 16);
    if (!(fl & 0x1)) continue;  // RTF_UP
    if ((group & m) != (d & m)) continue;
    const int prefix = __builtin_popcount(m);
    const long met = std::strtol(metric.c_str(), nullptr, 10);
    if (prefix > best_prefix || (prefix == best_prefix && met < best_metric)) {
      best = iface;
      best_prefix = prefix;
      best_metric = met;
    }
  }
  return best;
}

std::vector<std::string> igmp_members(const std::string& proc_net_igmp, uint32_t group) {
  std::vector<std::string> out;
  std::istringstream in(proc_net_igmp);
  std::string line, device;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream f(line);
    if (line[0] != '\t' && line[0] != ' ') {
      std::string idx;
      f >> idx >> device;  // "1\tlo        :     1      V3"; a long name touches the ':'
      device = device.substr(0, device.find(':'));
      continue;
    }
    std::string hex;
    uint32_t g;
    if (f >> hex && parse_proc_address(hex, &g) && g == group && !device.empty() &&
        std::find(out.begin(), out.end(), device) == out.end())
      out.push_back(device);
  }
  return out;
}

Exposure exposure(const std::string& proc_net_route, const std::string& proc_net_igmp, uint32_t group,
                  const std::vector<std::string>& allowed) {
  Exposure e;
  auto allowed_if = [&](const std::string& i) { return std::find(allowed.begin(), allowed.end(), i) != allowed.end(); };
  auto add = [&](const std::string& i, const std::string& why) {
    if (std::find(e.interfaces.begin(), e.interfaces.end(), i) == e.interfaces.end()) e.interfaces.push_back(i);
    e.reasons.push_back(why);
  };
  const std::optional<std::string> via = route_interface(proc_net_route, group);
  if (via && !allowed_if(*via))
    add(*via, "the route to " + dotted(group) + " leaves through " + *via + ", so the bus joins the group there");
  for (const auto& i : igmp_members(proc_net_igmp, group))
    if (!allowed_if(i)) add(i, i + " has joined " + dotted(group) + " (/proc/net/igmp)");
  return e;
}

Exposure host_exposure(const std::string& url, const std::vector<std::string>& allowed) {
  const std::optional<BusAddress> a = parse_udpm_url(url);
  if (!a) return {};
  return exposure(read_text("/proc/net/route"), read_text("/proc/net/igmp"), a->group, allowed);
}

int64_t warn_if_exposed(const std::string& process, const std::string& url, const BusGuardParams& params) {
  const Exposure e = host_exposure(url, params.allowed_interfaces);
  if (e.closed()) return 0;
  std::string list;
  for (const auto& i : e.interfaces) list += (list.empty() ? "" : ", ") + i;
  std::string why;
  for (const auto& r : e.reasons) why += (why.empty() ? "" : "; ") + r;
  std::fprintf(stderr,
               "%s: warning: the LCM bus %s is reachable from %s, which bus.allowed_interfaces does not allow (%s); "
               "any host there can publish CMD_VEL. Close it: tools/bus-firewall apply\n",
               process.c_str(), url.c_str(), list.c_str(), why.c_str());
  return static_cast<int64_t>(e.interfaces.size());
}

}  // namespace evade::bus
