#pragma once
// midpoint: the implicit midpoint rule on Hamilton's equations in (q, p = M(q)·qd),
// a symplectic and symmetric method of order 2: with a fixed step its energy error
// stays bounded (it oscillates, O(h²)) over arbitrarily long runs of a conservative
// system, where other methods drift. For long simulations of undamped mechanisms.
//
// Each step of h from (q0, p0, y0), with the midpoint qm = (q0 + q1)/2, pm, ym alike:
//
//   vm = M(qm)⁻¹·pm,   (qdd_m, yd_m) = accelerations(t + h/2, qm, vm, ym)
//   q1 = q0 + h·vm
//   p1 = p0 + h·(M(qm)·qdd_m + Ṁ(qm, vm)·vm)      (ṗ = M·qdd + Ṁ·qd)
//   y1 = y0 + h·yd_m
//
// solved by fixed-point iteration, switching to Newton when it contracts slowly (fast
// motion, large step): its matrix I - dG/dz from the system's exact Jacobians where it
// has them (DynamicSystem::exact_acceleration_derivatives) and no extra states, else by
// forward differences of the map; until the update stops
// shrinking at the level of rounding (a loose solve would break the symplectic map),
// at most options.max_newton_iterations iterations (counted as newton_iterations;
// Jacobians as jacobian_evaluations). Only the DynamicSystem interface is used (its
// jacobians() for the exact Newton matrix, midpoint.cpp): M·x = (f(q, 0, λ·x) - f(q, 0, 0))/λ
// (f is linear in qdd; λ, a large power of two, keeps the rounding relative to M·x), so M costs
// n + 1 residuals; Ṁ·v is a central difference of M(q)·v along v
// (4 residuals), with a step of cbrt(eps) relative to q_scale (1 by default).
//
// Fixed step only (options.initial_step, the last step shortened to end at t_end);
// outputs from the quintic Hermite interpolant; qd and qdd at the step ends from
// p1 and one evaluation of the accelerations. A failed iteration is a NumericError
// naming the time.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_midpoint(IntegratorOptions options);

}  // namespace symdyn::runtime
