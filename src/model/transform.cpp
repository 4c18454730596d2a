#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <symdyn/model/errors.hpp>
#include <symdyn/model/transform.hpp>

namespace symdyn::model {
namespace {

bool is_axis(const Vec3& a, int k) {
  for (int i = 0; i < 3; ++i) {
    if (a[i] != Expr(i == k ? 1 : 0)) return false;
  }
  return true;
}

}  // namespace

Transform operator*(const Transform& a, const Transform& b) {
  Transform t = a;
  t *= b;
  return t;
}

Transform& Transform::operator*=(const Transform& b) {
  steps_.insert(steps_.end(), b.steps_.begin(), b.steps_.end());
  return *this;
}

bool Transform::has_rotation() const {
  return std::any_of(steps_.begin(), steps_.end(), [](const Step& s) { return s.is_rotation; });
}

bool Transform::starts_with(const Transform& prefix) const {
  return prefix.steps_.size() <= steps_.size() &&
         std::equal(prefix.steps_.begin(), prefix.steps_.end(), steps_.begin());
}

Transform Transform::after(std::size_t n) const {
  Transform t;
  t.steps_.assign(steps_.begin() + static_cast<std::ptrdiff_t>(std::min(n, steps_.size())),
                  steps_.end());
  return t;
}

// Rodrigues: R = c·I + s·[k]x + (1 - c)·k·kᵀ; the elementary axes give the
// familiar Rx, Ry, Rz of docs/models.md with no zero terms to fold.
Mat3 Transform::rotation_matrix(const Vec3& k, Expr angle) {
  const Expr c = cos(angle);
  const Expr s = sin(angle);
  const Expr one(1);
  const Expr zero(0);
  if (is_axis(k, 0)) return {one, zero, zero, zero, c, -s, zero, s, c};
  if (is_axis(k, 1)) return {c, zero, s, zero, one, zero, -s, zero, c};
  if (is_axis(k, 2)) return {c, -s, zero, s, c, zero, zero, zero, one};
  const Expr v = 1 - c;
  return {c + v * k[0] * k[0],        v * k[0] * k[1] - s * k[2], v * k[0] * k[2] + s * k[1],
          v * k[1] * k[0] + s * k[2], c + v * k[1] * k[1],        v * k[1] * k[2] - s * k[0],
          v * k[2] * k[0] - s * k[1], v * k[2] * k[1] + s * k[0], c + v * k[2] * k[2]};
}

// x = Σ (rotation before step)·displacement, in one pass with R.
Transform::Pose Transform::pose() const {
  Pose p{identity3(), zero3(), {}};
  for (const Step& s : steps_) {
    if (s.is_rotation) {
      p.axes.emplace_back(p.R * s.axis, s.angle);
      p.R = p.R * rotation_matrix(s.axis, s.angle);
    } else {
      p.x = p.x + p.R * s.displacement;
    }
  }
  return p;
}

Transform Tdisp(Expr x, Expr y, Expr z) {
  Transform t;
  t.steps_.push_back({false, {x, y, z}, {}, Expr(0)});
  return t;
}

Transform Trot(const Vec3& axis, Expr angle) {
  double norm2 = 0.0;
  for (Expr a : axis) {
    if (!a.is_number())
      throw ModelError(fmt::format("Trot: the axis must be constant, got '{}'", a.str()));
    norm2 += a.number().to_double() * a.number().to_double();
  }
  if (std::abs(norm2 - 1.0) > 1e-12) {
    throw ModelError(fmt::format("Trot: the axis ({}, {}, {}) is not a unit vector", axis[0].str(),
                                 axis[1].str(), axis[2].str()));
  }
  Transform t;
  t.steps_.push_back({true, {}, axis, angle});
  return t;
}

Transform Trotx(Expr angle) {
  return Trot({Expr(1), Expr(0), Expr(0)}, angle);
}
Transform Troty(Expr angle) {
  return Trot({Expr(0), Expr(1), Expr(0)}, angle);
}
Transform Trotz(Expr angle) {
  return Trot({Expr(0), Expr(0), Expr(1)}, angle);
}

}  // namespace symdyn::model
