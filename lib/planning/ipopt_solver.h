// The IPOPT peer of CeresMpcSolver: the same MPC problem (planning::Problem)
// solved by IPOPT 3.11 through its Ipopt::TNLP interface with exact first
// and second derivatives (or L-BFGS), as the paper's code does through
// CasADi (which, like here, keeps the states as variables and the unicycle
// model as equality constraints: multiple shooting). It starts from given
// controls (zeros by default) with the states rolled out from them, so that
// it and Ceres can start from the same point. Eliminating
// the states by the dynamics gives exactly Ceres' single-shooting problem:
// same cost, same bounds, same rate limits, same barrier constraints.
// The planner's own additions to the paper's problem (Problem::v_cap,
// relax, reach, own_motion, penetration_weight) are not in its NLP.
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
  double tol = 1e-8;              // IPOPT's scaled NLP error at which it stops
  double constr_viol_tol = 1e-4;  // ... with constraint violation below this (IPOPT's default)
  double compl_inf_tol = 1e-4;    // ... and complementarity below this (IPOPT's default)
  int max_iter = 1000;
  int print_level = 0;
  bool limited_memory = false;  // L-BFGS instead of the exact Hessian
  double mu_init = 0.1;         // initial barrier parameter (IPOPT's default; lower near the answer)
  double bound_push = 0.01;     // how far the start is moved into the bounds (bound_push and bound_frac)
  std::vector<double> start_u;  // 2N controls to start from (states rolled out from them); empty: zeros
};

IpoptResult solve_with_ipopt(const Problem& pb, const IpoptOptions& opts = {});

}  // namespace evade::planning
