#pragma once
// SUNDIALS ARKODE (ARKStep) as a runtime integrator: a fully implicit diagonally
// implicit Runge-Kutta method of order 4 (ARKODE's SDIRK-5-3-4, five stages, L-stable,
// with an embedded third-order error estimate) on the first-order form x = (q, qd, y)
// (2n + m), Newton iterations with a dense linear solver and ARKODE's
// difference-quotient Jacobian, under our error weights (ErrorWeights, through
// ARKStepWFtolerances). A one-step stiff solver beside cvode's multistep BDF: it
// restarts at no cost after a discontinuity and damps stiff modes at every order.
//
// Steps, outputs, failures and statistics as for cvode (cvode_integrator.hpp):
// one step at a time, never past t_end, output instants from ARKODE's Hermite
// interpolating polynomial (ARKStepGetDky), so the outputs never change the steps.
// With options.fixed_step, steps of initial_step without error test (for order studies).

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_arkode(IntegratorOptions options);

}  // namespace symdyn::runtime
