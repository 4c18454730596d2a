#pragma once
// One step of the classical Runge-Kutta method (the rk4 integrator's step)
// and its exact derivatives, for control (model-predictive control, iLQR,
// DDP): the discrete-time transition x1 = Φ(x0, u) of x = (q, qd) under
// xd = f(x, u) = (qd, qdd(q, qd, u)), u generalized forces added on the
// coordinates and held over the step, with
//
//   A = ∂x1/∂x0 (2n x 2n),   B = ∂x1/∂u (2n x n),
//
// the tangent map carried through the four stages (stage k at x_k with
// ∂x_k/∂x0 = I + c_k·h·∂k_{k-1}/∂x0, and likewise for u), each stage's
// ∂f/∂x and ∂f/∂u from MultibodySystem::dynamics_derivatives: exact where the
// model was generated with its derivatives, the derivatives of the very map
// the step computes (not of the flow it approximates), as MuJoCo's
// mjd_transitionFD gives them by differences.

#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::runtime {

struct StepDerivatives {
  State next;  // x1 at t + h
  Matrix A;    // (2n x 2n) ∂(q1, qd1)/∂(q0, qd0)
  Matrix B;    // (2n x n)  ∂(q1, qd1)/∂u
};

// Throws ModelError for a system with extra states (their equations are not
// differentiated), a step that is not finite and positive, or u of the wrong
// size; NumericError as dynamics_derivatives.
void rk4_step_derivatives(MultibodySystem& system, const State& s, const Vector& u, double h,
                          StepDerivatives& out);

}  // namespace symdyn::runtime
