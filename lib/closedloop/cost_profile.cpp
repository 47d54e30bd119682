#include "closedloop/cost_profile.h"

#include <algorithm>
#include <cstdio>

namespace evade::closedloop {

CostFit fit_cost(const std::vector<CpuSample>& samples) {
  CostFit f;
  f.n = samples.size();
  if (samples.empty()) return f;
  double sk = 0, sc = 0;
  for (const auto& s : samples) {
    sk += s.k;
    sc += s.cpu_s;
  }
  const double n = static_cast<double>(samples.size());
  const double mk = sk / n, mc = sc / n;
  double skk = 0, skc = 0;
  for (const auto& s : samples) {
    skk += (s.k - mk) * (s.k - mk);
    skc += (s.k - mk) * (s.cpu_s - mc);
  }
  f.per_k_s = skk > 0 ? std::max(0.0, skc / skk) : 0.0;
  f.base_s = std::max(0.0, mc - f.per_k_s * mk);
  return f;
}

namespace {
double total_s(const std::vector<CpuSample>& samples) {
  double t = 0;
  for (const auto& s : samples) t += s.cpu_s;
  return t;
}

std::string line(const char* fmt, const std::string& name, double a, double b, size_t n, double total) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, name.c_str(), a, b, n, total);
  return buf;
}
}  // namespace

std::string suggested_costs(const LockstepResult& profiled) {
  std::string out = "  costs:\n";
  for (const auto& [name, p] : profiled.processes) {
    if (p.samples.empty()) continue;
    const CostFit f = fit_cost(p.samples);
    const char* fmt = name == "sim" ? "    %s: {callback_s: %.7f, packet_s: %.7f}  # %zu callbacks, %.3f s CPU\n"
                                    : "    %s: {callback_s: %.7f, publish_s: %.7f}  # %zu callbacks, %.3f s CPU\n";
    out += line(fmt, name, f.base_s, f.per_k_s, f.n, total_s(p.samples) + total_s(p.plan_samples));
  }
  auto it = profiled.processes.find("planner");
  if (it != profiled.processes.end() && !it->second.plan_samples.empty()) {
    const CostFit plan = fit_cost(it->second.plan_samples);
    const double callback = fit_cost(it->second.samples).base_s;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "  planner_base_s: %.7f\n  planner_per_iteration_s: %.8f  # %zu PLAN cycles, %.3f s CPU\n",
                  std::max(0.0, plan.base_s - callback), plan.per_k_s, plan.n, total_s(it->second.plan_samples));
    out += buf;
  }
  return out;
}

}  // namespace evade::closedloop
