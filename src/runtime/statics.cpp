#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/spd_solver.hpp>
#include <symdyn/runtime/statics.hpp>

namespace symdyn::runtime {

namespace {

// Residual at qd = qdd = 0 with the locked entries zeroed.
double static_residual(DynamicSystem& sys, const State& s, const std::vector<bool>& locked,
                       Vector& f) {
  const Vector zero = Vector::Zero(sys.num_coordinates());
  const Vector yd = Vector::Zero(sys.num_extra_states());
  Vector g;
  sys.residual(s, zero, yd, f, g);
  for (int j = 0; j < f.size(); ++j) {
    if (locked[j]) f(j) = 0.0;
  }
  return f.norm();
}

// The residual at a trial point of the line search: a state the system refuses
// (a dependent parameter out of its domain) counts as no decrease, so that a
// shorter step is tried; the full step, taken when none decreases, says why.
double trial_residual(DynamicSystem& sys, const State& s, const std::vector<bool>& locked,
                      Vector& f) {
  try {
    return static_residual(sys, s, locked, f);
  } catch (const NumericError&) {
    return INFINITY;
  }
}

// Why the iteration matrix is singular: the model's reason (an angle sequence
// at its singular configuration) when it knows one, else its null direction.
std::string singular_because(DynamicSystem& sys, const State& s, const Matrix& A) {
  if (auto why = sys.explain_singular(s, A)) return *why;
  return "along " + null_direction(A, [&](int j) { return sys.coordinate_name(j); });
}

}  // namespace

std::string StaticsReport::summary() const {
  return fmt::format("static equilibrium after {} iterations: |f| = {:.3e}, last |dq| = {:.3e}",
                     iterations, residual_norm, step_norm);
}

StaticsReport solve_statics(DynamicSystem& sys, const State& start, const StaticsOptions& options) {
  const int n = sys.num_coordinates();
  std::vector<bool> locked(n, false);
  for (int j : options.locked) {
    if (j < 0 || j >= n) throw ModelError(fmt::format("statics: no coordinate {} to lock", j));
    locked[j] = true;
  }
  StaticsReport r;
  r.state = start;
  r.state.qd.setZero();
  Vector f(n), ftrial(n);
  Matrix M, C, K;
  double fnorm = static_residual(sys, r.state, locked, f);
  const double stop = options.tolerance * std::sqrt(static_cast<double>(std::max(n, 1)));
  for (r.iterations = 1; r.iterations <= options.max_iterations; ++r.iterations) {
    sys.jacobians(r.state, Vector::Zero(n), M, C, K);
    Matrix A = options.mass_weight * M + K;
    for (int j = 0; j < n; ++j) {
      if (!locked[j]) continue;
      A.row(j).setZero();
      A.col(j).setZero();
      A(j, j) = 1.0;
    }
    const Eigen::FullPivLU<Matrix> lu(A);
    if (!lu.isInvertible()) {
      throw NumericError(fmt::format(
          "statics: iteration matrix {}·M + K is singular at iteration {} (|f| = {:.3e}): {}",
          options.mass_weight, r.iterations, fnorm, singular_because(sys, r.state, A)));
    }
    const Vector dq = -lu.solve(f);
    // Backtracking on |f|: halve while the residual does not decrease.
    double alpha = 1.0;
    State trial = r.state;
    trial.q = r.state.q + dq;
    double tnorm = trial_residual(sys, trial, locked, ftrial);
    for (int halving = 0; options.line_search && !(tnorm < fnorm) && halving < 30; ++halving) {
      alpha *= 0.5;
      trial.q = r.state.q + alpha * dq;
      tnorm = trial_residual(sys, trial, locked, ftrial);
    }
    if (!(tnorm <
          fnorm)) {  // no decrease found: take the full step (EasyDyn); a refusal there stops
      alpha = 1.0;
      trial.q = r.state.q + dq;
      tnorm = static_residual(sys, trial, locked, ftrial);
    }
    r.state = trial;
    f = ftrial;
    fnorm = tnorm;
    const double previous = r.step_norm;
    r.step_norm = alpha * dq.norm();
    r.residual_norm = fnorm;
    if (!std::isfinite(fnorm)) break;
    // With w M in the matrix the iteration converges linearly, with ratio
    // rho = |dq_k| / |dq_k-1|; the distance left is about |dq| rho / (1 - rho),
    // larger than |dq| when rho > 1/2 (EasyDyn stopped on |dq| alone).
    const double rho = r.iterations > 1 && previous > 0.0 ? r.step_norm / previous : 0.0;
    const double remaining = rho < 1.0 ? r.step_norm * std::max(1.0, rho / (1.0 - rho)) : INFINITY;
    if (remaining <= stop) return r;
  }
  throw NumericError(fmt::format(
      "statics: no equilibrium found after {} iterations (|f| = {:.3e}, last |dq| = {:.3e}, "
      "tolerance {:.3e})",
      std::min(r.iterations, options.max_iterations), fnorm, r.step_norm, stop));
}

}  // namespace symdyn::runtime
