#pragma once
// Explicit Runge-Kutta integrators on the first-order form
//
//   x = (q, qd, y)  (2n + m),   dx/dt = (qd, qdd, yd)  with (qdd, yd) = accelerations(x).
//
// rk4: the classic fourth-order method with a fixed step (options.initial_step),
// the last one shortened to end at t_end; outputs from the quintic Hermite
// interpolant. 4 evaluations per step (the last evaluation of a step is the first
// of the next).
//
// dopri5: Dormand and Prince's 5(4) pair with local extrapolation (the fifth-order
// solution is kept), 6 evaluations per step (first same as last), the error of the
// embedded fourth-order solution under the error weights (ErrorWeights), a PI step-size
// controller (exponents 0.17 and 0.04, safety 0.9, change bounded in [1/5, 10]), and
// its fourth-order continuous extension for output instants (Hairer, Norsett and
// Wanner, Solving ODEs I, II.6). A non-finite value in a stage rejects the step
// (h divided by 4). With options.fixed_step, steps of initial_step without error test.

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

std::unique_ptr<Integrator> make_rk4(IntegratorOptions options);
std::unique_ptr<Integrator> make_dopri5(IntegratorOptions options);

}  // namespace symdyn::runtime
