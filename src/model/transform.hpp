#pragma once
// Homogeneous transformations as products of elementary motions.
//
//   Tdisp(x, y, z)      translation
//   Trotx(a), Troty(a), Trotz(a)   rotation about the local x, y, z axis
//   Trot(axis, a)       rotation by a about a constant unit axis (local frame)
//
// A product A·B·C is read left to right as successive motions of a moving
// frame (docs/models.md). A Transform keeps its elementary factors, not only the
// 4x4 matrix, because the angular velocity is exact and short when composed
// from them: w = Σ_k R_(before k)·axis_k·d(angle_k)/dt.

#include <vector>

#include <symdyn/model/vector3.hpp>

namespace symdyn::model {

class Transform {
 public:
  // One elementary motion: a translation, or a rotation by `angle` about `axis`.
  struct Step {
    bool is_rotation = false;
    Vec3 displacement;  // translation
    Vec3 axis;          // unit axis of a rotation, constant
    Expr angle;         // rotation angle
    friend bool operator==(const Step&, const Step&) = default;
  };

  Transform() = default;  // identity

  friend Transform operator*(const Transform& a, const Transform& b);
  Transform& operator*=(const Transform& b);

  const std::vector<Step>& steps() const { return steps_; }

  bool has_rotation() const;
  // Whether the first steps are those of `prefix`, the same expressions.
  bool starts_with(const Transform& prefix) const;
  // The steps after the first n: this = (first n steps)·after(n).
  Transform after(std::size_t n) const;

  Mat3 rotation() const;     // R
  Vec3 translation() const;  // x

  // Angular velocity in the frame the transformation starts from, given the
  // time derivative of each step's angle.
  template <class TimeDerivative>
  Vec3 angular_velocity(TimeDerivative&& d_dt) const {
    Mat3 R = identity3();
    Vec3 w = zero3();
    for (const Step& s : steps_) {
      if (!s.is_rotation) continue;
      w = w + d_dt(s.angle) * (R * s.axis);
      R = R * rotation_matrix(s.axis, s.angle);
    }
    return w;
  }

  static Mat3 rotation_matrix(const Vec3& axis, Expr angle);

 private:
  friend Transform Tdisp(Expr x, Expr y, Expr z);
  friend Transform Trot(const Vec3& axis, Expr angle);
  std::vector<Step> steps_;
};

Transform Tdisp(Expr x, Expr y, Expr z);
Transform Trotx(Expr angle);
Transform Troty(Expr angle);
Transform Trotz(Expr angle);
// Rotation about a constant unit axis; throws ModelError unless |axis| = 1.
Transform Trot(const Vec3& axis, Expr angle);

}  // namespace symdyn::model
