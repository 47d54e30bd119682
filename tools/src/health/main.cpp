// health: a terminal table of every evade process's HEALTH heartbeat,
// redrawn every health_board.refresh_period_s (table: health_board.h).
//
//   health [--config F] [--lcm-url U] [--expect a,b,c] [--no-colour]
//   health --once [--expect a,b,c]   listen health_board.once_listen_s, print
//                                    once; exit 1 when a process is stale or
//                                    an expected one was never heard, else 0
//   health --wait-received P:C[,P:C]  listen until process P's HEALTH counts
//                                    a message received on its input C (for
//                                    each), exit 0; exit 1 after
//                                    health_board.wait_timeout_s. A launcher
//                                    starts what depends on it afterwards
//                                    (tools/run_scenario: the simulator once
//                                    the planner has its ROUTE).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "bus/core.h"
#include "bus/live_bus.h"
#include "bus/process_main.h"
#include "health_board.h"

namespace {

constexpr const char* kName = "health";

struct Listener {
  evade::health::HealthBoard board;
  int64_t malformed = 0;
  void on(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    evade::health_t m;
    if (!evade::bus::decode(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size, &m)) {
      ++malformed;
      return;
    }
    board.add(m, evade::bus::wall_utime());
  }
};

// Handles messages until `until` (bus time) or a stop signal.
void listen_until(lcm::LCM& lcm, int64_t until) {
  const auto& stop = evade::bus::stop_on_signals();
  for (int64_t now = evade::bus::wall_utime(); now < until && !stop.load(); now = evade::bus::wall_utime())
    lcm.handleTimeout(int(std::max<int64_t>(1, (until - now) / 1000)));
}

void print(const Listener& l, const std::vector<std::string>& expected, const evade::health::HealthBoardParams& p,
           bool colour, bool clear) {
  if (clear) std::fputs("\033[H\033[2J", stdout);
  for (const auto& line : render_table(l.board, expected, evade::bus::wall_utime(), p, colour))
    std::printf("%s\n", line.c_str());
  if (l.malformed) std::printf("malformed HEALTH messages: %lld\n", static_cast<long long>(l.malformed));
  std::fflush(stdout);
}

// Listens until every wanted input has arrived (0) or the timeout (1).
int wait_received(lcm::LCM& lcm, Listener& listener, const std::vector<std::string>& texts,
                  const evade::health::HealthBoardParams& p) {
  std::vector<evade::health::InputWanted> wanted;
  for (const auto& t : texts) {
    evade::health::InputWanted w;
    std::string why;
    if (!evade::health::parse_input_wanted(t, &w, &why)) {
      std::fprintf(stderr, "%s: --wait-received: %s\n", kName, why.c_str());
      return 2;
    }
    wanted.push_back(w);
  }
  const int64_t until = evade::bus::wall_utime() + int64_t(p.wait_timeout_s * 1e6);
  const auto& stop = evade::bus::stop_on_signals();
  std::vector<std::string> left = inputs_not_received(listener.board, wanted);
  while (!left.empty() && !stop.load() && evade::bus::wall_utime() < until) {
    listen_until(lcm, std::min(until, evade::bus::wall_utime() + 100'000));
    left = inputs_not_received(listener.board, wanted);
  }
  for (const auto& w : left)
    std::fprintf(stderr, "%s: %s not received within %.1f s\n", kName, w.c_str(), p.wait_timeout_s);
  return left.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade health board: one row per process from HEALTH"};
  evade::bus::CommonOptions opts;
  evade::bus::add_robot_options(app, opts, false);  // --config, --robot
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local)");
  bool once = false, no_colour = false;
  std::vector<std::string> expected;
  app.add_flag("--once", once, "listen once_listen_s, print once, exit 1 if stale or missing");
  app.add_option("--expect", expected, "processes that must be heard (comma-separated)")->delimiter(',');
  std::vector<std::string> wait_for;
  app.add_option("--wait-received", wait_for,
                 "PROCESS:CHANNEL,...: exit 0 once each process's HEALTH counts a message on that input, "
                 "1 after health_board.wait_timeout_s")
      ->delimiter(',');
  app.add_flag("--no-colour", no_colour, "no ANSI colours (default: colours on a terminal)");
  CLI11_PARSE(app, argc, argv);

  evade::health::HealthBoardParams params;
  try {
    const evade::config::Node root = evade::bus::load_config_or_exit(kName, opts);
    params = evade::health::HealthBoardParams::from_config(root.section("health_board"));
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
  const std::string url = opts.lcm_url.empty() ? evade::bus::default_lcm_url() : opts.lcm_url;
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "%s: cannot start LCM on %s\n", kName, url.c_str());
    return 2;
  }
  Listener listener;
  using evade::bus::kHealthChannel;
  lcm.subscribe(kHealthChannel, &Listener::on, &listener);
  const bool colour = !no_colour && ::isatty(STDOUT_FILENO);

  if (!wait_for.empty()) return wait_received(lcm, listener, wait_for, params);
  if (once) {
    listen_until(lcm, evade::bus::wall_utime() + int64_t(params.once_listen_s * 1e6));
    print(listener, expected, params, colour, false);
    const auto v = evade::health::judge(listener.board, expected, evade::bus::wall_utime(), params);
    for (const auto& n : v.stale) std::fprintf(stderr, "%s: %s is stale\n", kName, n.c_str());
    for (const auto& n : v.missing) std::fprintf(stderr, "%s: %s was never heard\n", kName, n.c_str());
    if (listener.board.processes().empty() && expected.empty())
      std::fprintf(stderr, "%s: no HEALTH heard on %s\n", kName, url.c_str());
    return v.ok() ? 0 : 1;
  }
  const auto& stop = evade::bus::stop_on_signals();
  while (!stop.load()) {
    listen_until(lcm, evade::bus::wall_utime() + int64_t(params.refresh_period_s * 1e6));
    if (!stop.load()) print(listener, expected, params, colour, true);
  }
  return 0;
}
