#include "metrics/plan_status.h"

#include "evade/plan_t.hpp"

namespace evade::metrics {

const char* plan_status_name(int status) {
  switch (status) {
    case evade::plan_t::STATUS_OK:
      return "ok";
    case evade::plan_t::STATUS_FALLBACK:
      return "fallback";
    case evade::plan_t::STATUS_STOPPING:
      return "stopping";
    case evade::plan_t::STATUS_STALE_INPUT:
      return "stale-input";
    case evade::plan_t::STATUS_NO_ROUTE:
      return "no-route";
    case evade::plan_t::STATUS_GOAL:
      return "goal";
    case evade::plan_t::STATUS_RECOVERING:
      return "recovering";
    case evade::plan_t::STATUS_BLOCKED:
      return "blocked";
    default:
      return "unknown";
  }
}

}  // namespace evade::metrics
