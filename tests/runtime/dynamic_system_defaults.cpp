// Test-only definitions of DynamicSystem's non-pure members, used while
// src/runtime/dynamic_system.cpp (written with the integrators) is not in this
// tree: tests/runtime/CMakeLists.txt compiles this file only when that one is
// absent, so the two never link together.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "runtime/dynamic_system.hpp"

namespace symdyn::runtime {

std::string DynamicSystem::coordinate_name(int i) const { return fmt::format("q{}", i); }
std::string DynamicSystem::extra_state_name(int i) const { return fmt::format("y{}", i); }

void DynamicSystem::jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K) {
  const int n = num_coordinates();
  M.resize(n, n);
  C.resize(n, n);
  K.resize(n, n);
  const Vector yd = Vector::Zero(num_extra_states());
  Vector fp, fm, g;
  State p = s;
  Vector a = qdd;
  for (int j = 0; j < n; ++j) {
    const double ha = 1e-6 * std::max(1.0, std::abs(qdd(j)));
    a(j) = qdd(j) + ha;
    residual(s, a, yd, fp, g);
    a(j) = qdd(j) - ha;
    residual(s, a, yd, fm, g);
    a(j) = qdd(j);
    M.col(j) = (fp - fm) / (2.0 * ha);
    const double hq = 1e-6 * std::max(1.0, std::abs(s.q(j)));
    p.q(j) = s.q(j) + hq;
    residual(p, qdd, yd, fp, g);
    p.q(j) = s.q(j) - hq;
    residual(p, qdd, yd, fm, g);
    p.q(j) = s.q(j);
    K.col(j) = (fp - fm) / (2.0 * hq);
    const double hv = 1e-6 * std::max(1.0, std::abs(s.qd(j)));
    p.qd(j) = s.qd(j) + hv;
    residual(p, qdd, yd, fp, g);
    p.qd(j) = s.qd(j) - hv;
    residual(p, qdd, yd, fm, g);
    p.qd(j) = s.qd(j);
    C.col(j) = (fp - fm) / (2.0 * hv);
  }
}

}  // namespace symdyn::runtime
