// The IPOPT peer of CeresMpcSolver: the same MPC problem (planning::Problem)
// solved by IPOPT 3.11 through its Ipopt::TNLP interface with exact first
// and second derivatives, cold-started from zeros, as the paper's code does
// through CasADi (which, like here, keeps the states as variables and the
// unicycle model as equality constraints: multiple shooting). Eliminating
// the states by the dynamics gives exactly Ceres' single-shooting problem:
// same cost, same bounds, same rate limits, same barrier constraints.
// Used by the benchmark and as a cross-check in tests, not by the planner.
#pragma once

#include <vector>

#include "planning/problem.h"

namespace evade::planning {

struct IpoptResult {
  bool solved = false;       // IPOPT reported Solve_Succeeded / Solved_To_Acceptable_Level
  int status = 0;            // Ipopt::ApplicationReturnStatus
  std::vector<double> u;     // 2N controls
  double cost = 0;           // paper's J of u (single-shooting rollout)
  double max_violation = 0;  // of u, as for the Ceres solver
  int iterations = 0;
};

struct IpoptOptions {
  double tol = 1e-8;
  int max_iter = 1000;
  int print_level = 0;
};

IpoptResult solve_with_ipopt(const Problem& pb, const IpoptOptions& opts = {});

}  // namespace evade::planning
