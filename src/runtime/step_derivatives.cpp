#include <fmt/format.h>

#include <cmath>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/step_derivatives.hpp>

namespace symdyn::runtime {
namespace {

// One stage: f at x (2n) and its Jacobians ∂f/∂x (2n x 2n) and ∂f/∂u (2n x n).
struct Stage {
  Vector f;
  Matrix fx, fu;
};

void evaluate_stage(MultibodySystem& system, double t, const Vector& x, const Vector& u,
                    DynamicsDerivatives& d, Stage& stage) {
  const int n = system.num_coordinates();
  State s;
  s.t = t;
  s.q = x.head(n);
  s.qd = x.tail(n);
  system.dynamics_derivatives(s, d, true, u);
  stage.f.resize(2 * n);
  stage.f << s.qd, d.qdd;
  stage.fx = Matrix::Zero(2 * n, 2 * n);
  stage.fx.topRightCorner(n, n).setIdentity();
  stage.fx.bottomLeftCorner(n, n) = d.dqdd_dq;
  stage.fx.bottomRightCorner(n, n) = d.dqdd_dqd;
  stage.fu = Matrix::Zero(2 * n, n);
  stage.fu.bottomRows(n) = d.dqdd_dtau;
}

}  // namespace

void rk4_step_derivatives(MultibodySystem& system, const State& s, const Vector& u, double h,
                          StepDerivatives& out) {
  const int n = system.num_coordinates();
  if (system.num_extra_states() > 0) {
    throw ModelError(
        "rk4_step_derivatives: the system has extra states, whose equations are not "
        "differentiated");
  }
  if (!(std::isfinite(h) && h > 0.0))
    throw ModelError(fmt::format("rk4_step_derivatives: step {} is not positive", h));
  if (u.size() != n) {
    throw ModelError(fmt::format("rk4_step_derivatives: {} generalized forces u given; expected {}",
                                 u.size(), n));
  }
  Vector x0(2 * n);
  x0 << s.q, s.qd;
  // The stages of rk4 at t + c·h, x0 + c·h·k_previous, weights 1/6, 1/3, 1/3, 1/6.
  constexpr double c[4] = {0.0, 0.5, 0.5, 1.0};
  constexpr double weight[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  DynamicsDerivatives d;
  Stage stage;
  Vector x = x0, sum = Vector::Zero(2 * n);
  Matrix dx_dx0 = Matrix::Identity(2 * n, 2 * n),
         dx_du = Matrix::Zero(2 * n, n);  // of the stage's point
  Matrix dk_dx0, dk_du;                   // of the stage's slope
  out.A = Matrix::Identity(2 * n, 2 * n);
  out.B = Matrix::Zero(2 * n, n);
  for (int k = 0; k < 4; ++k) {
    if (k > 0) {
      x = x0 + c[k] * h * stage.f;
      dx_dx0 = Matrix::Identity(2 * n, 2 * n) + c[k] * h * dk_dx0;
      dx_du = c[k] * h * dk_du;
    }
    evaluate_stage(system, s.t + c[k] * h, x, u, d, stage);
    dk_dx0 = stage.fx * dx_dx0;
    dk_du = stage.fx * dx_du + stage.fu;
    sum += weight[k] * stage.f;
    out.A += h * weight[k] * dk_dx0;
    out.B += h * weight[k] * dk_du;
  }
  const Vector x1 = x0 + h * sum;
  out.next.t = s.t + h;
  out.next.q = x1.head(n);
  out.next.qd = x1.tail(n);
  out.next.y = s.y;
}

}  // namespace symdyn::runtime
