#pragma once
// Cardan (Tait-Bryan) angles of a rotation in a chosen axis order.
//
// For the order (i, j, k), three distinct axes among x, y, z, the angles
// (a, b, c) satisfy R = R_i(a) R_j(b) R_k(c), with R_x, R_y, R_z the
// elementary rotations of docs/models.md; b lies in [-pi/2, pi/2], and the angles
// are singular (gimbal lock) at |b| = pi/2.

#include <array>
#include <string_view>

#include <symdyn/runtime/kinematics.hpp>

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

}  // namespace symdyn::runtime
