#pragma once
// SUNDIALS CVODE as a runtime integrator: variable-order (1-5) variable-step BDF on
// the first-order form x = (q, qd, y) (2n + m), Newton iterations with a dense
// linear solver and CVODE's difference-quotient Jacobian. The reference stiff solver.
// Its error weights are ours (ErrorWeights, through CVodeWFtolerances) at the current x.
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
