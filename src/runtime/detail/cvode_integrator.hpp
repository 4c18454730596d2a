#pragma once
// SUNDIALS CVODE as a runtime integrator: variable-order (1-5) variable-step BDF on
// the first-order form x = (q, qd, y) (2n + m), Newton iterations with a dense
// linear solver and CVODE's difference-quotient Jacobian. The reference stiff solver.
// Its error weights are ours (ErrorWeights, through CVodeWFtolerances) at the current x.
//
// What the tolerance bounds. BDF's error in a step is the method's own (no local
// extrapolation, unlike dopri5's, whose steps err far below the tolerance), and on a
// conservative mechanism it is dissipative: the free slider-crank loses energy at a steady
// 0.37·tol of it per step, 5.5e-4 of it over 100 s (150 000 steps) at tol 1e-8, where
// dopri5 drifts 8.8e-7. Neither the order (at most 2, 3 or 4) nor a tighter Newton
// iteration changes it (bench/results/integrator_accuracy.md). As newmark.hpp's, the
// tolerance is transformed: each step's error is held within rtol^(1/3) of the weights
// (CVODE is given rtol^(4/3) and atol·rtol^(1/3)), so that N steps of a method of order
// about 3, N ~ tol^(-1/4), end about in proportion to the tolerance; at 1e-8 the drift is
// 3.4e-6 of the energy. CVODE's tolerance stops at 1e-14 (rtol = 3.2e-11), and
// tightest_tolerance() says so to global_tolerance; it may refuse less on a long run
// ("too much accuracy requested": the slider-crank's 100 s at 1e-14, rtol = 3.2e-11,
// whose crank angle reaches 3 900 rad against a weight of 2e-14).
//
// CVODE takes one step at a time (CV_ONE_STEP) and never steps past t_end (stop
// time); the output instants inside each step come from CVODE's interpolating
// polynomial (CVodeGetDky), so they never change the steps; with no output
// instants, every step is delivered. A non-finite (qdd, yd), or a NumericError from the
// system, is reported to CVODE as a recoverable failure (it retries with a smaller
// step); if CVODE gives up, the NumericError names CVODE's flag, its message and
// the last non-finite value seen. fixed_step is not available (OptionError).
//
// Statistics: steps, rejected steps (error test and convergence failures), Newton
// iterations and Jacobian evaluations as CVODE counts them; right-hand side
// evaluations counted by us (including those of the difference-quotient Jacobian
// and one per output instant for qdd and yd).

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_cvode(IntegratorOptions options);

}  // namespace symdyn::runtime
