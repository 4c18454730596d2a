#include <fmt/format.h>

#include <cmath>
#include <limits>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

std::string DynamicSystem::coordinate_name(int i) const {
  return fmt::format("q{}", i);
}

std::string DynamicSystem::extra_state_name(int i) const {
  return fmt::format("y{}", i);
}

namespace {

// Central differences have an error O(d²·f''') + O(eps·|f|/d): d = eps^(1/3)
// balances them. Relative to the value, with a floor of 1 so that a zero
// coordinate still gets a step that is not lost in rounding.
double central_step(double x) {
  static const double base = std::cbrt(std::numeric_limits<double>::epsilon());
  const double d = base * std::max(1.0, std::abs(x));
  // The step actually taken is (x + d) - x after rounding: divide by that.
  const double xp = x + d;
  return xp - x;
}

}  // namespace

// J(:, j) = (f(x + d·e_j) - f(x - d·e_j)) / 2d for x in {qdd, qd, q}, other
// arguments held; the extra states and yd play no part in f's derivatives here.
void DynamicSystem::jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K) {
  const int n = num_coordinates();
  const int m = num_extra_states();
  M.resize(n, n);
  C.resize(n, n);
  K.resize(n, n);
  const Vector yd = Vector::Zero(m);
  Vector fp(n), fm(n), g(m);
  State sp = s;
  Vector qddp = qdd;

  // Perturbs one component of `x` (a member of sp, or qddp), fills column j of J.
  auto column = [&](Vector& x, const Vector& x0, Matrix& J, int j) {
    const double d = central_step(x0[j]);
    x[j] = x0[j] + d;
    residual(sp, qddp, yd, fp, g);
    x[j] = x0[j] - d;
    residual(sp, qddp, yd, fm, g);
    x[j] = x0[j];
    J.col(j) = (fp - fm) / (2.0 * d);
  };
  for (int j = 0; j < n; ++j) {
    column(qddp, qdd, M, j);
    column(sp.qd, s.qd, C, j);
    column(sp.q, s.q, K, j);
  }
}

}  // namespace symdyn::runtime
