#include "closedloop/run_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "evade/plan_t.hpp"
#include "metrics/geometry.h"
#include "metrics/plan_status.h"

namespace evade::closedloop {

double truth_clearance(const evade::sim_truth_t& t) {
  const metrics::OrientedRect robot{{t.x, t.y}, t.yaw, t.footprint_length, t.footprint_width};
  double clear = 1e9;
  for (const auto& o : t.obstacles) {
    const double c = o.shape == "box"
                         ? metrics::clearance(robot, metrics::OrientedRect{{o.x, o.y}, o.yaw, o.length, o.width})
                         : metrics::clearance(robot, metrics::Vec2{o.x, o.y}, o.radius);
    clear = std::min(clear, c);
  }
  return clear;
}

RunMonitor::RunMonitor(const RunMonitorParams& params) : Core("run_monitor"), p_(params) {
  subscribe<evade::sim_truth_t>("SIM_TRUTH", [this](const evade::sim_truth_t& t) { on_truth(t); });
  subscribe<evade::plan_t>("PLAN", [this](const evade::plan_t& p) {
    plan_status_ = p.status;
    solve_ms_ = p.solve_time_us * 1e-3;
  });
  every(200'000, [this] { check_stall(); });
}

void RunMonitor::on_truth(const evade::sim_truth_t& t) {
  last_truth_now_ = now();
  if (t0_ < 0) t0_ = t.utime;
  elapsed_s_ = (t.utime - t0_) * 1e-6;
  const double to_goal = std::hypot(t.x - t.goal_x, t.y - t.goal_y);
  const double clear = truth_clearance(t);
  min_clear_ = std::min(min_clear_, clear);
  if (!p_.quiet) print_progress(t, to_goal, clear);
  if (result_ != kRunning) return;
  if (to_goal <= t.goal_tolerance) {
    if (goal_at_ < 0) goal_at_ = t.utime;
    if (t.utime - goal_at_ >= std::llround(p_.margin_s * 1e6)) finish(kGoal, "goal reached");
  } else if (t.duration_s > 0 && elapsed_s_ >= t.duration_s) {
    finish(kDuration, "duration passed");
  }
}

// On a terminal one line rewritten 5 times a second; in a log file a new
// line every 2 s of scenario time.
void RunMonitor::print_progress(const evade::sim_truth_t& t, double to_goal, double clear) {
  const int64_t period = p_.tty ? 200'000 : 2'000'000;
  if (t.utime - last_print_ < period) return;
  last_print_ = t.utime;
  std::fprintf(stderr,
               "%s  t %5.1f s  to goal %6.2f m  v %5.2f m/s  clearance %5.2f m (min %5.2f)  plan %-8s %5.2f ms %s",
               p_.tty ? "\r" : "", elapsed_s_, to_goal, t.v, clear, min_clear_,
               plan_status_ < 0 ? "-" : metrics::plan_status_name(plan_status_), solve_ms_, p_.tty ? "" : "\n");
  std::fflush(stderr);
}

void RunMonitor::check_stall() {
  if (result_ == kRunning && last_truth_now_ >= 0 && now() - last_truth_now_ > std::llround(p_.stall_s * 1e6))
    finish(kStalled, "SIM_TRUTH stopped arriving");
}

void RunMonitor::finish(int code, const std::string& why) {
  result_ = code;
  if (!p_.quiet && p_.tty) std::fprintf(stderr, "\n");
  if (code == kStalled)
    std::fprintf(stderr, "run-monitor: %s\n", why.c_str());
  else
    std::fprintf(stderr, "run-monitor: %s at t %.1f s\n", why.c_str(), elapsed_s_);
}

}  // namespace evade::closedloop
