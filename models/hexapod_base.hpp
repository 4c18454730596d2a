#pragma once
// What amru5 and hexapod_tree share (docs/models.md 5 and 7): the main body on a
// floating base and the six hips.
#include <array>
#include <numbers>

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

// The main body "body", floating: its coordinates x, y, z, yaw, pitch, roll
// (the first six; its height z is returned, to start from).
inline model::Expr floating_main_body(model::Model& m) {
  using namespace symdyn::model;
  const Expr x = m.coordinate("x"), y = m.coordinate("y"), z = m.coordinate("z");
  const Expr yaw = m.coordinate("yaw"), pitch = m.coordinate("pitch"), roll = m.coordinate("roll");
  m.body("body")
      .mass(60)
      .inertia(2.0, 7.4, 9.0)
      .motion(Tdisp(x, y, z) * Trotz(yaw) * Troty(pitch) * Trotx(roll));
  return z;
}

}  // namespace symdyn::models
