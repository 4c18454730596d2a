#pragma once
// Static equilibrium: q such that f(t, q, qd = 0, qdd = 0) = 0 (extra states
// held at their given values).
//
// Newton-like iterations as in EasyDyn: dq = -(w M + K)^-1 f with
// M = df/dqdd, K = df/dq and w = mass_weight (100 in EasyDyn: the mass term
// regularizes a singular K, at the price of slower convergence; 0 gives plain
// Newton). Improvements over EasyDyn: a backtracking line search on |f|
// (halving the step while |f| does not decrease, up to 30 times; if no step
// decreases |f| the full step is taken), and a clear report or error.
// Locked coordinates keep their value (residual zeroed, identity row and
// column). Converged when |dq| <= tolerance * sqrt(n) (EasyDyn's test) and,
// when the iteration converges only linearly (ratio rho of successive steps
// above 1/2, as the mass term makes it), when the estimated remaining
// distance |dq| rho / (1 - rho) is below it too.

#include <string>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

struct StaticsOptions {
  double mass_weight = 100.0;
  double tolerance = 1e-8;
  int max_iterations = 500;
  bool line_search = true;
  std::vector<int> locked;  // coordinate indices held fixed
};

struct StaticsReport {
  State state;  // the equilibrium (qd = 0)
  int iterations = 0;
  double residual_norm = 0;  // |f| at the solution, over free coordinates
  double step_norm = 0;      // |dq| of the last iteration
  std::string summary() const;
};

// Throws NumericError (with iterations, |f| and |dq|) when it does not
// converge within max_iterations, or when the iteration matrix is singular.
StaticsReport solve_statics(DynamicSystem& system, const State& start,
                            const StaticsOptions& options = {});

}  // namespace symdyn::runtime
