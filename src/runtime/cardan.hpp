#pragma once
// Cardan (Tait-Bryan) angles of a rotation in a chosen axis order.
//
// For the order (i, j, k), three distinct axes among x, y, z, the angles
// (a, b, c) satisfy R = R_i(a) R_j(b) R_k(c), with R_x, R_y, R_z the
// elementary rotations of docs/models.md; b lies in [-pi/2, pi/2], and the angles
// are singular (gimbal lock) at |b| = pi/2.

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/kinematics_derivatives.hpp>

namespace symdyn::runtime {

struct CardanOrder {
  std::array<int, 3> axes{0, 1, 2};  // i, j, k in {0, 1, 2}, distinct
  // Parses "xyz", "zyx", ...; throws ModelError for anything else.
  static CardanOrder parse(std::string_view order);
};

// Elementary rotation about axis (0, 1, 2) by angle a.
Mat3 elementary_rotation(int axis, double a);
// R_i(a) R_j(b) R_k(c)
Mat3 cardan_rotation(const CardanOrder& order, const Vec3& angles);
// The angles (a, b, c) of R.
Vec3 cardan_angles(const CardanOrder& order, const Mat3& R);
// E(angles) with w = E(angles) . (ad, bd, cd): the angular velocity of the
// rotated frame in the axes of the fixed frame, from the angle rates.
Mat3 cardan_rate_matrix(const CardanOrder& order, const Vec3& angles);

// The same for any scalar T (the automatic differentiation of force elements,
// kinematics_derivatives.hpp); the functions above are these for double.
template <class T>
Mat3T<T> elementary_rotation(int axis, const T& a) {
  using std::cos, std::sin;
  const T c = cos(a), s = sin(a);
  const int j = (axis + 1) % 3, k = (axis + 2) % 3;
  Mat3T<T> R = Mat3T<T>::Zero();
  R(axis, axis) = T(1.0);
  R(j, j) = c;
  R(j, k) = -s;
  R(k, j) = s;
  R(k, k) = c;
  return R;
}

template <class T>
Vec3T<T> cardan_angles(const CardanOrder& o, const Mat3T<T>& R) {
  using std::asin, std::atan2;
  const int i = o.axes[0], j = o.axes[1], k = o.axes[2];
  // +1 for the cyclic orders (xyz, yzx, zxy), -1 for the others.
  const double e = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const T b = asin(std::clamp(T(e * R(i, k)), T(-1.0), T(1.0)));
  const T a = atan2(T(-e * R(j, k)), R(k, k));
  const T c = atan2(T(-e * R(i, j)), R(i, i));
  return Vec3T<T>(a, b, c);
}

template <class T>
Mat3T<T> cardan_rate_matrix(const CardanOrder& o, const Vec3T<T>& angles) {
  // w = ad e_i + bd R_i(a) e_j + cd R_i(a) R_j(b) e_k
  const Mat3T<T> Ri = elementary_rotation(o.axes[0], angles(0));
  const Mat3T<T> Rij = Ri * elementary_rotation(o.axes[1], angles(1));
  Mat3T<T> E = Mat3T<T>::Zero();
  E(o.axes[0], 0) = T(1.0);
  E.col(1) = Ri.col(o.axes[1]);
  E.col(2) = Rij.col(o.axes[2]);
  return E;
}

}  // namespace symdyn::runtime
