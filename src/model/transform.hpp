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

#include <utility>
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

  // R and x of the product, and each rotation's axis in the frame the
  // product starts from, with its angle: the angular velocity is
  // w = Σ d(angle)/dt · axis, exact and short.
  struct Pose {
    Mat3 R;
    Vec3 x;
    std::vector<std::pair<Vec3, Expr>> axes;
  };
  Pose pose() const;

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
