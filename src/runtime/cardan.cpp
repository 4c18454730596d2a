#include <fmt/format.h>

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
  return elementary_rotation<double>(axis, a);
}

Mat3 cardan_rotation(const CardanOrder& o, const Vec3& angles) {
  return elementary_rotation(o.axes[0], angles(0)) * elementary_rotation(o.axes[1], angles(1)) *
         elementary_rotation(o.axes[2], angles(2));
}

Vec3 cardan_angles(const CardanOrder& o, const Mat3& R) {
  return cardan_angles<double>(o, R);
}

Mat3 cardan_rate_matrix(const CardanOrder& o, const Vec3& angles) {
  return cardan_rate_matrix<double>(o, angles);
}

}  // namespace symdyn::runtime
