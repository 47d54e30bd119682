// run-monitor [--lcm-url URL] [--margin-s S] [--quiet]
// Watches SIM_TRUTH and PLAN during a scenario run: prints a live progress
// line (time, distance to goal, speed, clearance, planner status) and exits
// when the goal is reached (0), when the scenario's duration has passed
// (1), or when SIM_TRUTH stops arriving for --stall-s (3).
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "bus/core.h"
#include "bus/live_bus.h"
#include "evade/plan_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "metrics/geometry.h"

namespace {

const char* status_name(int s) {
  switch (s) {
    case evade::plan_t::STATUS_OK: return "ok";
    case evade::plan_t::STATUS_FALLBACK: return "fallback";
    case evade::plan_t::STATUS_STOPPING: return "stopping";
    case evade::plan_t::STATUS_STALE_INPUT: return "stale";
    case evade::plan_t::STATUS_NO_ROUTE: return "no-route";
    case evade::plan_t::STATUS_GOAL: return "goal";
    default: return "?";
  }
}

class Monitor : public evade::bus::Core {
 public:
  Monitor(double margin_s, double stall_s, bool quiet)
      : Core("run_monitor"), margin_us_(margin_s * 1e6), stall_us_(stall_s * 1e6), quiet_(quiet) {
    subscribe<evade::sim_truth_t>("SIM_TRUTH", [this](const evade::sim_truth_t& t) { on_truth(t); });
    subscribe<evade::plan_t>("PLAN", [this](const evade::plan_t& p) {
      plan_status_ = p.status;
      solve_ms_ = p.solve_time_us * 1e-3;
    });
    every(200'000, [this] { check_stall(); });
  }
  int result = -1;  // exit status once decided

 private:
  void on_truth(const evade::sim_truth_t& t) {
    last_truth_now_ = now();
    if (t0_ < 0) t0_ = t.utime;
    double elapsed = (t.utime - t0_) * 1e-6;
    double to_goal = std::hypot(t.x - t.goal_x, t.y - t.goal_y);
    evade::metrics::OrientedRect robot{{t.x, t.y}, t.yaw, t.footprint_length, t.footprint_width};
    double clear = 1e9;
    for (const auto& o : t.obstacles) {
      double c = o.shape == "box"
                     ? evade::metrics::clearance(robot, evade::metrics::OrientedRect{{o.x, o.y}, o.yaw, o.length, o.width})
                     : evade::metrics::clearance(robot, evade::metrics::Vec2{o.x, o.y}, o.radius);
      clear = std::min(clear, c);
    }
    min_clear_ = std::min(min_clear_, clear);
    // On a terminal one line rewritten 5 times a second; in a log file a
    // new line every 2 s.
    const int64_t print_period = tty_ ? 200'000 : 2'000'000;
    if (!quiet_ && t.utime - last_print_ >= print_period) {
      last_print_ = t.utime;
      std::fprintf(stderr, "%s  t %5.1f s  to goal %6.2f m  v %5.2f m/s  clearance %5.2f m (min %5.2f)  plan %-8s %5.2f ms %s",
                   tty_ ? "\r" : "", elapsed, to_goal, t.v, clear, min_clear_, plan_status_ < 0 ? "-" : status_name(plan_status_),
                   solve_ms_, tty_ ? "" : "\n");
      std::fflush(stderr);
    }
    if (result >= 0) return;
    if (to_goal <= t.goal_tolerance) {
      if (goal_at_ < 0) goal_at_ = t.utime;
      if (t.utime - goal_at_ >= margin_us_) finish(0, "goal reached", elapsed);
    } else if (t.duration_s > 0 && elapsed >= t.duration_s) {
      finish(1, "duration passed", elapsed);
    }
  }
  void check_stall() {
    if (result < 0 && last_truth_now_ >= 0 && now() - last_truth_now_ > stall_us_)
      finish(3, "SIM_TRUTH stopped arriving", -1);
  }
  void finish(int code, const char* why, double elapsed) {
    result = code;
    if (!quiet_ && tty_) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "run-monitor: %s%s\n", why,
                 elapsed >= 0 ? (" at t " + std::to_string(elapsed).substr(0, 6) + " s").c_str() : "");
  }

  int64_t t0_ = -1, last_print_ = 0, goal_at_ = -1, last_truth_now_ = -1;
  double min_clear_ = 1e9, solve_ms_ = 0;
  int plan_status_ = -1;
  int64_t margin_us_, stall_us_;
  bool quiet_;
  bool tty_ = ::isatty(2) != 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Progress of a scenario run; exits at the goal or the scenario's duration"};
  std::string url;
  double margin_s = 0.5, stall_s = 5.0;
  bool quiet = false;
  app.add_option("--lcm-url", url, "LCM URL");
  app.add_option("--margin-s", margin_s, "keep watching this long after the goal is reached");
  app.add_option("--stall-s", stall_s, "give up when SIM_TRUTH is silent this long");
  app.add_flag("--quiet", quiet, "no progress line");
  CLI11_PARSE(app, argc, argv);
  try {
    evade::bus::LiveBus bus(url.empty() ? evade::bus::default_lcm_url() : url);
    Monitor mon(margin_s, stall_s, quiet);
    bus.add(mon);
    const auto& stop = evade::bus::stop_on_signals();
    while (mon.result < 0 && !stop.load()) bus.spin_once(50);
    return mon.result < 0 ? 130 : mon.result;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run-monitor: %s\n", e.what());
    return 2;
  }
}
