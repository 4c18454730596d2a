#pragma once
// What amru5 and hexapod_tree share (docs/models.md 5 and 7): the main body on a
// floating base and the six hips.
#include <array>
#include <numbers>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::models {

// A hip at (x, y) in the main body's frame; its leg points outwards, yawed
// by psi = +pi/2 on the left (y > 0) and -pi/2 on the right.
struct Hip {
  double x, y;
  double psi() const { return y > 0 ? std::numbers::pi / 2 : -std::numbers::pi / 2; }
};

inline constexpr std::array<Hip, 6> hips = {
    {{0.5, 0.3}, {0.5, -0.3}, {0.0, 0.3}, {0.0, -0.3}, {-0.5, 0.3}, {-0.5, -0.3}}};

// The main body "body", floating: position q0..q2, yaw q3, pitch q4, roll q5.
inline model::Body& floating_main_body(model::Model& m, const std::vector<model::Expr>& q) {
  using namespace symdyn::model;
  return m.body("body")
      .mass(60)
      .inertia(2.0, 7.4, 9.0)
      .motion(Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]));
}

}  // namespace symdyn::models
