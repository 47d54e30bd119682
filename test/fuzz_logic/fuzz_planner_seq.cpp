// Logic fuzzer: the planner core over random well-formed ODOMETRY, ROUTE
// and OBSTACLE_PREDICTIONS sequences (sequence.h). Its PLAN and CMD_VEL
// must stay finite.
#include <algorithm>

#include "config/config.h"
#include "messages.h"
#include "planning/params.h"
#include "planning/planner_core.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace evade;
  static const planning::PlannerParams params = [] {
    planning::PlannerParams p = planning::PlannerParams::from_config(
        config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
    p.solver.max_cycle_iterations =
        std::min(p.solver.max_cycle_iterations, 200);  // bounded time per cycle under the sanitizers
    return p;
  }();
  fuzz::Bytes in(data, size);
  planning::PlannerParams p = params;
  static const planning::Mode modes[] = {planning::Mode::kEvade, planning::Mode::kDcbf, planning::Mode::kMpc,
                                         planning::Mode::kCbf,   planning::Mode::kKf,   planning::Mode::kCbfCurvefit};
  p.mode = modes[in.u8() % 6];
  planning::PlannerCore core(p);
  static const std::vector<uint8_t> straight = [] {
    evade::path_t r{};
    r.utime = fuzz::kStart;
    r.n = 2;
    r.x = {-10.0, 10.0};
    r.y = {0.0, 0.0};
    return bus::encode(r);
  }();
  fuzz::run_sequence(
      core,
      {{"ODOMETRY", fuzz::odometry},
       {"ROUTE", fuzz::route},
       {"OBSTACLE_PREDICTIONS", [](fuzz::Bytes& b, int64_t now) { return fuzz::predictions(b, now, 64); }}},
      in, 24, {}, {{"ROUTE", straight}});
  return 0;
}
