// The names of PLAN.status codes (lcmtypes/plan_t.lcm), one word each, for
// every place that prints a plan's status: the closed loop's progress line,
// the viewer's HUD. A code the table does not know is "unknown".
#pragma once

#include <cstdint>

namespace evade::metrics {

const char* plan_status_name(int status);

}  // namespace evade::metrics
