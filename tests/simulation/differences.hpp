#pragma once
// Derivatives by differences for the simulation tests: central differences
// extrapolated by Richardson, and the residual's Jacobians made of them.

#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::testing {

// d g(x)/dx by central differences at h and h/2 combined by Richardson's
// extrapolation: error O(h⁴) + rounding/h. g gives a double or a Vector.
template <class F>
auto richardson(F g, double x, double h) {
  using Result = decltype(g(x));
  const auto central = [&](double step) -> Result {
    return (g(x + step) - g(x - step)) / (2 * step);
  };
  return Result((4 * central(h / 2) - central(h)) / 3);
}

// K = df/dq and C = df/dqd of the residual f at (s, qdd), column j by
// richardson with the step step(x_j).
template <class Step>
void residual_jacobians_by_differences(runtime::MultibodySystem& system, const runtime::State& s,
                                       const runtime::Vector& qdd, runtime::Matrix& C,
                                       runtime::Matrix& K, Step step) {
  using runtime::State;
  using runtime::Vector;
  const int n = system.num_coordinates();
  C.resize(n, n);
  K.resize(n, n);
  const Vector yd = Vector::Zero(system.num_extra_states());
  for (int j = 0; j < n; ++j) {
    const auto along = [&](Vector State::*member) {
      return [&, member](double x) {
        State p = s;
        (p.*member)(j) = x;
        Vector f, g;
        system.residual(p, qdd, yd, f, g);
        return f;
      };
    };
    K.col(j) = richardson(along(&State::q), s.q(j), step(s.q(j)));
    C.col(j) = richardson(along(&State::qd), s.qd(j), step(s.qd(j)));
  }
}

}  // namespace symdyn::testing
