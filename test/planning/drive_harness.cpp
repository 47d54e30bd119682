#include "drive_harness.h"

#include <cmath>

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::planning::testing {

namespace {

// The harness's base reaches each command at once, so the plan's first
// speed is the one it should get: planner.brake_ahead leads a base that
// ramps to its commands, and would brake this one two steps in one.
PlannerParams for_an_ideal_base(PlannerParams p) {
  p.brake_ahead = false;
  return p;
}

}  // namespace

DriveHarness::DriveHarness(const PlannerParams& p, RobotState start) : core_(for_an_ideal_base(p)), robot_(start) {
  bus_.add(core_);
}

void DriveHarness::run(double duration_s, const std::function<void(const Step&)>& inputs,
                       const std::function<void(const evade::plan_t&, const Step&)>& on_plan,
                       const std::function<void(const Step&)>& observe) {
  for (int i = 0; i * kPeriodS < duration_s; ++i) {
    Step s;
    s.i = i;
    s.t = i * kPeriodS;
    s.now = kStartUs + static_cast<int64_t>(std::llround(s.t * 1e6));
    if (inputs) inputs(s);
    evade::odometry_t o{};
    o.utime = s.now;
    o.x = robot_.x;
    o.y = robot_.y;
    o.yaw = robot_.yaw;
    o.v = robot_.v;
    o.omega = robot_.omega;
    bus_.inject("ODOMETRY", o, s.now);
    for (const auto& e : bus_.take_published()) {
      if (e.channel == "CMD_VEL") {
        evade::cmd_vel_t c{};
        bus::decode(e.data.data(), e.data.size(), &c);
        if (!std::isfinite(c.v) || !std::isfinite(c.omega)) ++nonfinite_commands_;
        robot_.v = c.v;
        robot_.omega = c.omega;
      } else if (e.channel == "PLAN") {
        evade::plan_t pl{};
        bus::decode(e.data.data(), e.data.size(), &pl);
        if (on_plan) on_plan(pl, s);
      }
    }
    if (observe) observe(s);
    robot_.x += robot_.v * std::cos(robot_.yaw) * kPeriodS;
    robot_.y += robot_.v * std::sin(robot_.yaw) * kPeriodS;
    robot_.yaw += robot_.omega * kPeriodS;
  }
}

}  // namespace evade::planning::testing
