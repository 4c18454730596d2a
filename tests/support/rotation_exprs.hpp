#pragma once
// Rotation matrices of expressions and the angular velocity they imply, with
// their own chain-rule derivative, for the tests and benchmarks of the
// simplifier (the angular velocity of Euler angles must reach its closed form).

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::testing::rotation_exprs {

using namespace symdyn::symbolic;

// d e / d x for the kinds kinematics use, written out apart from the engine's
// diff so that it can check it.
inline Expr derivative(Expr e, Expr x, std::map<std::uint32_t, Expr>& memo) {
  if (auto it = memo.find(e.id()); it != memo.end()) return it->second;
  Expr d = 0;
  switch (e.kind()) {
    case Kind::Rational:
    case Kind::Real:
      d = 0;
      break;
    case Kind::Symbol:
      d = e == x ? 1 : 0;
      break;
    case Kind::Add:
      for (Expr a : e.args()) d = d + derivative(a, x, memo);
      break;
    case Kind::Mul:
      for (std::size_t i = 0; i < e.args().size(); ++i) {
        Expr term = derivative(e.arg(i), x, memo);
        for (std::size_t j = 0; j < e.args().size(); ++j) {
          if (j != i) term = term * e.arg(j);
        }
        d = d + term;
      }
      break;
    case Kind::Pow:
      d = e.arg(1) * pow(e.arg(0), Expr(e.arg(1).number() - Number(1))) *
          derivative(e.arg(0), x, memo);
      break;
    case Kind::Sin:
      d = cos(e.arg(0)) * derivative(e.arg(0), x, memo);
      break;
    case Kind::Cos:
      d = -sin(e.arg(0)) * derivative(e.arg(0), x, memo);
      break;
    default:
      throw std::logic_error(std::string("derivative: unsupported kind ") +
                             std::string(info(e.kind()).name));
  }
  memo.emplace(e.id(), d);
  return d;
}

using Mat3 = std::array<std::array<Expr, 3>, 3>;

inline Mat3 product(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Expr s = 0;
      for (int k = 0; k < 3; ++k) s = s + a[i][k] * b[k][j];
      c[i][j] = s;
    }
  }
  return c;
}

inline Mat3 rot_x(Expr q) {
  return {{{1, 0, 0}, {0, cos(q), -sin(q)}, {0, sin(q), cos(q)}}};
}
inline Mat3 rot_y(Expr q) {
  return {{{cos(q), 0, sin(q)}, {0, 1, 0}, {-sin(q), 0, cos(q)}}};
}
inline Mat3 rot_z(Expr q) {
  return {{{cos(q), -sin(q), 0}, {sin(q), cos(q), 0}, {0, 0, 1}}};
}

// w such that skew(w) = dR/dt R^T, dR/dt = sum_i dR/dq_i qd_i.
inline std::array<Expr, 3> angular_velocity(const Mat3& r, std::span<const Expr> q,
                                            std::span<const Expr> qd) {
  Mat3 rdot;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Expr s = 0;
      for (std::size_t k = 0; k < q.size(); ++k) {
        std::map<std::uint32_t, Expr> memo;
        s = s + derivative(r[i][j], q[k], memo) * qd[k];
      }
      rdot[i][j] = s;
    }
  }
  Mat3 rt;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rt[i][j] = r[j][i];
  }
  const Mat3 w = product(rdot, rt);
  return {w[2][1], w[0][2], w[1][0]};
}

}  // namespace symdyn::testing::rotation_exprs
