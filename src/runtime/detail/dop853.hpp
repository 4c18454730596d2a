#pragma once
// dop853: Dormand and Prince's explicit Runge-Kutta pair of order 8 with error
// estimators of orders 5 and 3 (Hairer, Norsett and Wanner, Solving ODEs I, II.10),
// on the first-order form x = (q, qd, y) (2n + m). 12 evaluations per step (the
// last one, at the step end, is the first of the next step), the combined 5/3 error
// estimate under the error weights (ErrorWeights), step size h·0.9·err^(-1/8) within
// [h/3, 6·h], and the seventh-order continuous extension for output instants (3 more
// evaluations in a step that holds one, plus one for qdd and yd at each instant).
// For smooth problems at tight tolerances. With options.fixed_step, steps of
// initial_step without error test.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_dop853(IntegratorOptions options);

}  // namespace symdyn::runtime
