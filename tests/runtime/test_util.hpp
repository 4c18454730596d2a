#pragma once
// Helpers shared by the runtime tests: seeded random states, the double
// pendulum's Lagrange equations written independently of the fixture.

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime::test {

inline std::mt19937& rng() {
  static std::mt19937 g(20240607u);
  return g;
}
inline double uniform(double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng());
}
inline Vector random_vector(int n, double lo, double hi) {
  Vector v(n);
  for (int j = 0; j < n; ++j) v(j) = uniform(lo, hi);
  return v;
}
inline State make_state(double t, const Vector& q, const Vector& qd, const Vector& y = Vector()) {
  // Copy-constructed members: GCC 12 reports a false array-bounds warning on
  // Eigen's vectorized assignment of 1-entry vectors.
  return State{t, Vector(q), Vector(qd), Vector(y)};
}

// Double pendulum of docs/models.md (l = m = 1, Izz = 1/12, g = 9.81 along -y):
// Lagrange's M(q) and h(q, qd) with a = l1, b = l2/2, c = l1/2.
struct Lagrange {
  Matrix M = Matrix(2, 2);
  Vector h = Vector(2);
  Vector dV = Vector(2);  // gradient of the potential
};
inline Lagrange double_pendulum_lagrange(const Vector& q, const Vector& qd) {
  const double I = 1.0 / 12.0, a = 1.0, b = 0.5, c = 0.5, g = 9.81;
  const double c1 = std::cos(q(1)), s1 = std::sin(q(1));
  Lagrange L;
  L.M(0, 0) = 2.0 * I + c * c + a * a + b * b + 2.0 * a * b * c1;
  L.M(0, 1) = L.M(1, 0) = I + b * b + a * b * c1;
  L.M(1, 1) = I + b * b;
  L.dV(0) = g * (c * std::cos(q(0)) + a * std::cos(q(0)) + b * std::cos(q(0) + q(1)));
  L.dV(1) = g * b * std::cos(q(0) + q(1));
  L.h(0) = -a * b * s1 * (2.0 * qd(0) * qd(1) + qd(1) * qd(1)) + L.dV(0);
  L.h(1) = a * b * s1 * qd(0) * qd(0) + L.dV(1);
  return L;
}

}  // namespace symdyn::runtime::test
