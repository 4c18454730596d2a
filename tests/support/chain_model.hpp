#pragma once
// The chain_N model of docs/models.md, "absolute" variant, as
// 4x4 homogeneous transforms over any scalar: double (the numerical
// reference), symbolic::Expr, or GiNaC::ex (the benchmark's baseline). The
// engine knows no mechanics; tests and benchmarks build this model themselves.
//
//   body 0:  T_0 = Trotz(q_0)·Tdisp(L/2, 0, 0)
//   body k:  T_k = T_{k-1}·Tdisp(L/2, 0, 0)·Trot_k(q_k)·Tdisp(L/2, 0, 0)
// with Trot_k about z, y, x for k mod 3 = 0, 1, 2; every T_k is expressed in
// the ground frame (the full product of the chain up to k).

#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace symdyn::testing {

template <class T>
using Mat4 = std::array<std::array<T, 4>, 4>;  // row-major, [row][column]

template <class T>
Mat4<T> identity4() {
  Mat4<T> m;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) m[i][j] = T(i == j ? 1 : 0);
  }
  return m;
}

template <class T>
Mat4<T> operator*(const Mat4<T>& a, const Mat4<T>& b) {
  Mat4<T> c;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      T sum = a[i][0] * b[0][j];
      for (int k = 1; k < 4; ++k) sum = sum + a[i][k] * b[k][j];
      c[i][j] = sum;
    }
  }
  return c;
}

// Rotation by `angle` about axis 0 (x), 1 (y) or 2 (z).
template <class T>
Mat4<T> rotation(int axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T c = T(cos(angle));
  const T s = T(sin(angle));
  const int i = (axis + 1) % 3;  // the plane of the rotation: (i, j), right-handed
  const int j = (axis + 2) % 3;
  Mat4<T> m = identity4<T>();
  m[i][i] = c;
  m[i][j] = -s;
  m[j][i] = s;
  m[j][j] = c;
  return m;
}

template <class T>
Mat4<T> displacement_x(const T& x) {
  Mat4<T> m = identity4<T>();
  m[0][3] = x;
  return m;
}

// The pose of every body in the ground frame, given the joint angles q
// (size N) and the half length L/2.
template <class T>
std::vector<Mat4<T>> chain_absolute(std::span<const T> q, const T& half_length) {
  static constexpr int kAxisOfBody[3] = {2, 1, 0};  // z, y, x for k mod 3 = 0, 1, 2
  const Mat4<T> half = displacement_x(half_length);
  std::vector<Mat4<T>> poses;
  poses.reserve(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) {
    const Mat4<T> joint = rotation(kAxisOfBody[k % 3], q[k]) * half;
    poses.push_back(k == 0 ? joint : poses.back() * half * joint);
  }
  return poses;
}

// The 12 entries of a pose that vary (rotation and translation: rows 0..2).
template <class T>
void append_pose_entries(const Mat4<T>& pose, std::vector<T>& out) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) out.push_back(pose[i][j]);
  }
}

}  // namespace symdyn::testing
