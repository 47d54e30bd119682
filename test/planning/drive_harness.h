// The closed loop of the planner's tests: a PlannerCore on the in-memory bus
// and a robot that follows CMD_VEL exactly (a unicycle, integrated at the
// odometry period). Shared by test/planning and test/occlusion.
#pragma once

#include <cstdint>
#include <functional>

#include "bus/memory_bus.h"
#include "evade/plan_t.hpp"
#include "planning/params.h"
#include "planning/planner_core.h"

namespace evade::planning::testing {

// The robot's pose and its current command.
struct RobotState {
  double x = 0, y = 0, yaw = 0, v = 0, omega = 0;
};

class DriveHarness {
 public:
  static constexpr double kPeriodS = 0.02;        // odometry at 50 Hz
  static constexpr int64_t kStartUs = 1'000'000;  // bus time of step 0

  // One step of the loop: index i, t = i kPeriodS (s since the start) and
  // its bus time now = kStartUs + t (us, rounded).
  struct Step {
    int i = 0;
    double t = 0;
    int64_t now = 0;
  };

  explicit DriveHarness(const PlannerParams& p, RobotState start = {});
  DriveHarness(const DriveHarness&) = delete;
  DriveHarness& operator=(const DriveHarness&) = delete;

  // Steps while i kPeriodS < duration_s, each:
  //   1. inputs(step): the test injects what arrives at step.now;
  //   2. ODOMETRY of the robot at step.now (its pose and current command);
  //   3. every PLAN published goes to on_plan(plan, step), every CMD_VEL
  //      becomes the robot's command, reached at once (so the core runs
  //      with planner.brake_ahead off: that leads a base that ramps);
  //   4. observe(step): the robot where it is at step.t, with its new command;
  //   5. the robot moves for kPeriodS.
  // Empty functions are skipped; robot() is the robot's state throughout.
  void run(double duration_s, const std::function<void(const Step&)>& inputs,
           const std::function<void(const evade::plan_t&, const Step&)>& on_plan,
           const std::function<void(const Step&)>& observe = {});

  bus::MemoryBus& bus() { return bus_; }
  PlannerCore& core() { return core_; }
  const RobotState& robot() const { return robot_; }
  // CMD_VELs with a non-finite v or omega (applied all the same).
  int nonfinite_commands() const { return nonfinite_commands_; }

 private:
  bus::MemoryBus bus_;
  PlannerCore core_;
  RobotState robot_;
  int nonfinite_commands_ = 0;
};

}  // namespace evade::planning::testing
