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
// Newmark: am = af = 0, beta = 1/4, gamma = 1/2 (the trapezoidal rule on (q, qd)).
// Generalized-alpha from rho_inf: am = (2·rho - 1)/(rho + 1), af = rho/(rho + 1),
// gamma = 1/2 - am + af, beta = (1 - am + af)²/4 (second order, unconditionally
// stable, high-frequency dissipation set by rho; rho = 1 gives back Newmark).
// a lags qdd by d·h (d = am - af): a step of h after one of h_prev takes a0 + d·(h -
// h_prev)·q''' for a0 (a0 = qdd0 at the start, h_prev = 0), so that neither a change of
// step nor the start makes an error of O(h²·|h - h_prev|·q''').
//
// Local error of a step, leading terms:
//   q:  cq·h³·q'''   cq = beta + d/2 - 1/6                                 (1/12 for Newmark)
//   qd: cv·h³·q''''  cv = (1 - gamma)·d²/2 + gamma·(1 + d)²/2 + c2 - 1/6,
//                    c2 = ((1 - af) - (1 - am)·(1 + d)² - am·d²)/2         (1/12 for Newmark)
//   y:  h³·y'''/12
// estimated with q''' = (qdd1 - qdd0)/h (cq·h²·(qdd1 - qdd0), Zienkiewicz-Xie's estimate),
// q'''' and y''' from divided differences of qdd and yd over this step and the one before
// (on the first step, with q''' and y'' at t0 from one explicit evaluation).
//
// Error test: a second-order method whose steps each make an error tol ends about
// N·tol ~ tol^(2/3) off (N ~ tol^(-1/3) steps). The step is accepted when
// sqrt(mean_i (e_i/w_i)²) <= sqrt(rtol) under the error weights w (ErrorWeights,
// integrator.hpp): each step's error is tol^(3/2) relative to the weights, and the error
// at t_end falls in proportion to the tolerance (RADAU5 transforms its tolerance for the
// same reason). The bound is never below 50 roundings of the weights (rtol < 5e-10):
// there the error stops falling, and tightest_tolerance() says so to global_tolerance.
// Step control: h·0.9·err^(-1/3) within [0.2, 5], no growth right after a rejection, h
// kept for a growth below 1.2 (so is the factorization of the iteration matrix); a Newton
// failure or a non-finite value divides h by 4 (EasyDyn). A PI controller does as well on
// smooth problems but changes h at every step, which excites the undamped stiff modes of
// the trapezoidal rule. The first step is Hairer-Wanner's starting step.
//
// Each step: prediction of qdd1 and yd1 by the parabola through the last accelerations,
// q1, qd1, y1 from the formulas of the scheme; modified Newton on (qdd1, yd1) with the
// iteration matrix
//   [ M + gamma'·h·C + beta'·h²·K     F_yd + h/2·F_y ]      beta'  = beta·c
//   [ gamma'·h·G_qd + beta'·h²·G_q    G_yd + h/2·G_y ]      gamma' = gamma·c
// (c = (1 - af)/(1 - am)), where M, C, K come from DynamicSystem::jacobians and the
// blocks of the extra states from forward differences of the residual (LuSolver). The
// iteration stops when its remaining error, rate/(1 - rate) times the last correction
// (the rate measured in this step, or carried over from the steps before and drifting
// towards 1 while unmeasured: Hairer-Wanner's test for Radau IIA), is below 0.05 of the
// step's local error estimate (of at most the test's bound at a fixed step), both in the
// norm of the error test; or when the correction is at rounding level. Its error is then
// a small part of the method's at any step, fixed steps included, and one iteration per
// step is the rule. The matrix is kept across iterations and steps, refactored when h
// changes, its Jacobians re-evaluated after a step whose rate exceeded 0.1 and, with a
// fresh start from the prediction, when the rate exceeds 0.5 or the iteration diverges.
// At the start, Newton with h = 0 computes accelerations consistent with the state.
//
// Dense output: the Hermite interpolants of SteppingIntegrator, qdd linear in the step.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_newmark(IntegratorOptions options);
std::unique_ptr<Integrator> make_generalized_alpha(IntegratorOptions options);

}  // namespace symdyn::runtime
