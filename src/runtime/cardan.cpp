#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <symdyn/runtime/cardan.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

CardanOrder CardanOrder::parse(std::string_view order) {
  CardanOrder o;
  const auto axis = [&](char c) {
    if (c < 'x' || c > 'z') {
      throw ModelError(fmt::format("Cardan order '{}': axes must be x, y or z", order));
    }
    return c - 'x';
  };
  if (order.size() != 3) {
    throw ModelError(fmt::format("Cardan order '{}': three axes expected", order));
  }
  for (int n = 0; n < 3; ++n) o.axes[n] = axis(order[n]);
  if (o.axes[0] == o.axes[1] || o.axes[1] == o.axes[2] || o.axes[0] == o.axes[2]) {
    throw ModelError(fmt::format("Cardan order '{}': the three axes must differ", order));
  }
  return o;
}

Mat3 elementary_rotation(int axis, double a) {
  const double c = std::cos(a), s = std::sin(a);
  const int j = (axis + 1) % 3, k = (axis + 2) % 3;
  Mat3 R = Mat3::Zero();
  R(axis, axis) = 1.0;
  R(j, j) = c;
  R(j, k) = -s;
  R(k, j) = s;
  R(k, k) = c;
  return R;
}

Mat3 cardan_rotation(const CardanOrder& o, const Vec3& angles) {
  return elementary_rotation(o.axes[0], angles(0)) * elementary_rotation(o.axes[1], angles(1)) *
         elementary_rotation(o.axes[2], angles(2));
}

Vec3 cardan_angles(const CardanOrder& o, const Mat3& R) {
  const int i = o.axes[0], j = o.axes[1], k = o.axes[2];
  // +1 for the cyclic orders (xyz, yzx, zxy), -1 for the others.
  const double e = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const double b = std::asin(std::clamp(e * R(i, k), -1.0, 1.0));
  const double a = std::atan2(-e * R(j, k), R(k, k));
  const double c = std::atan2(-e * R(i, j), R(i, i));
  return Vec3(a, b, c);
}

Mat3 cardan_rate_matrix(const CardanOrder& o, const Vec3& angles) {
  // w = ad e_i + bd R_i(a) e_j + cd R_i(a) R_j(b) e_k
  const Mat3 Ri = elementary_rotation(o.axes[0], angles(0));
  const Mat3 Rij = Ri * elementary_rotation(o.axes[1], angles(1));
  Mat3 E;
  E.col(0) = Mat3::Identity().col(o.axes[0]);
  E.col(1) = Ri.col(o.axes[1]);
  E.col(2) = Rij.col(o.axes[2]);
  return E;
}

}  // namespace symdyn::runtime
