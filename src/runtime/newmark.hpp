#pragma once
// Newmark (EasyDyn's scheme) and generalized-alpha: one implicit method family
// on the residual form f(t, q, qd, qdd, y) = 0, g(t, q, qd, y, yd) = 0.
//
// Arnold-Bruls' form of Chung-Hulbert's generalized-alpha, with an algorithmic
// acceleration a (a = qdd for Newmark):
//
//   (1 - am)·a1 + am·a0 = (1 - af)·qdd1 + af·qdd0
//   q1  = q0 + h·qd0 + h²·((1/2 - beta)·a0 + beta·a1)
//   qd1 = qd0 + h·((1 - gamma)·a0 + gamma·a1)
//   y1  = y0 + h/2·(yd0 + yd1)                              (trapezoidal)
//   f(t1, q1, qd1, qdd1, y1) = 0,  g(t1, q1, qd1, y1, yd1) = 0
//
// Newmark: am = af = 0, beta = 1/4, gamma = 1/2. Generalized-alpha from rho_inf:
// am = (2·rho - 1)/(rho + 1), af = rho/(rho + 1), gamma = 1/2 - am + af,
// beta = (1 - am + af)²/4 (second order, unconditionally stable, high-frequency
// dissipation set by rho; rho = 1 gives back Newmark).
//
// Each step: prediction qdd1 = qdd0, yd1 = yd0; modified Newton on (qdd1, yd1)
// with the iteration matrix
//   [ M + gamma'·h·C + beta'·h²·K     F_yd + h/2·F_y ]      beta'  = beta·c
//   [ gamma'·h·G_qd + beta'·h²·G_q    G_yd + h/2·G_y ]      gamma' = gamma·c
// (c = (1 - af)/(1 - am)), where M, C, K come from DynamicSystem::jacobians and the
// blocks of the extra states from forward differences of the residual. The matrix is
// kept across iterations and steps, refactored when h changes and re-evaluated when
// the iteration converges slowly (rate above 1/4) or diverges.
//
// Local error: h²·|qdd1 - qdd0|/12 (EasyDyn) for q; the trapezoidal errors
// h³·|q''''|/12 for qd and h³·|y'''|/12 for y, with q'''' and y''' from divided
// differences of qdd and yd over this step and the one before; RMS under the error
// weights (ErrorWeights, integrator.hpp). Outputs come from the quintic Hermite
// interpolant (integrator.hpp), so they never shorten a step. Step control: a
// Newton failure or a non-finite value divides h by 4 (EasyDyn); otherwise, the
// estimate being O(h³), the next step is h·r with r = 0.9·err^(-1/3) within
// [0.2, 4], kept at h when 1 <= r < 1.5 (the iteration matrix is refactored only
// when h changes).
// At the start, Newton with h = 0 computes accelerations consistent with the state.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_newmark(IntegratorOptions options);
std::unique_ptr<Integrator> make_generalized_alpha(IntegratorOptions options);

}  // namespace symdyn::runtime
