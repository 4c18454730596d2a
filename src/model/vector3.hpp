#pragma once
// 3-vectors and 3x3 matrices of expressions, for the kinematics.

#include <array>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::model {

using symbolic::Expr;

using Vec3 = std::array<Expr, 3>;
using Mat3 = std::array<Expr, 9>;  // row-major

inline Vec3 zero3() {
  return {Expr(0), Expr(0), Expr(0)};
}

inline bool is_zero(const Vec3& v) {
  return v[0].is_zero() && v[1].is_zero() && v[2].is_zero();
}

inline Mat3 identity3() {
  return {Expr(1), Expr(0), Expr(0), Expr(0), Expr(1), Expr(0), Expr(0), Expr(0), Expr(1)};
}

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator*(Expr s, const Vec3& a) {
  return {s * a[0], s * a[1], s * a[2]};
}

// Sums of three terms are built at once (the engine's n-ary add), not pairwise:
// the same expression, without interning the partial sums.
inline Expr sum3(Expr a, Expr b, Expr c) {
  const std::array<Expr, 3> terms{a, b, c};
  return symbolic::add(terms);
}

inline Expr dot(const Vec3& a, const Vec3& b) {
  return sum3(a[0] * b[0], a[1] * b[1], a[2] * b[2]);
}

inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A·b
inline Vec3 operator*(const Mat3& A, const Vec3& b) {
  return {sum3(A[0] * b[0], A[1] * b[1], A[2] * b[2]), sum3(A[3] * b[0], A[4] * b[1], A[5] * b[2]),
          sum3(A[6] * b[0], A[7] * b[1], A[8] * b[2])};
}

// Aᵀ·b
inline Vec3 transpose_times(const Mat3& A, const Vec3& b) {
  return {sum3(A[0] * b[0], A[3] * b[1], A[6] * b[2]), sum3(A[1] * b[0], A[4] * b[1], A[7] * b[2]),
          sum3(A[2] * b[0], A[5] * b[1], A[8] * b[2])};
}

// A·B
inline Mat3 operator*(const Mat3& A, const Mat3& B) {
  Mat3 C;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      C[3 * i + j] = sum3(A[3 * i] * B[j], A[3 * i + 1] * B[3 + j], A[3 * i + 2] * B[6 + j]);
  }
  return C;
}

}  // namespace symdyn::model
