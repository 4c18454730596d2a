// A 6-6 Stewart platform with prismatic legs (docs/models.md): the base is
// the ground, each leg a cylinder on a universal joint at the base and a
// piston sliding in it, whose end is a ball joint at the platform; the six
// loops close at the platform's attachments.
//
// The independent coordinates are the six leg lengths (base joint to ball
// joint): the actuators' own coordinates, so that the generalized forces on
// them are the leg forces, and the forward dynamics under given leg forces
// and the inverse dynamics (leg forces for a prescribed motion) are the
// system's own. The platform's pose and the legs' joint angles (18) are
// implicit: the loops' Newton iteration is the forward kinematics.
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

constexpr double base_radius = 0.5, platform_radius = 0.3;
constexpr double home_height = 0.85;         // platform G above the base
constexpr double attachment_below_g = 0.05;  // the platform's joints, below its G
constexpr double cylinder_g = 0.275;         // from the base joint, along the leg
constexpr double piston_g = 0.25;            // from the ball joint, back along the leg
constexpr double deg = std::numbers::pi / 180;

struct Point {
  double x, y, z;
};
// Leg i: its base joint at 120°·k ± 15° (k = i / 2), its platform joint 30°
// away from it (at 120°·k ∓ 45°: each base pair reaches two platform pairs).
Point base_joint(int i) {
  const double a = (120 * (i / 2) + (i % 2 ? 15 : -15)) * deg;
  return {base_radius * std::cos(a), base_radius * std::sin(a), 0};
}
Point platform_joint(int i) {  // in platform axes from its G
  const double a = (120 * (i / 2) + (i % 2 ? 45 : -45)) * deg;
  return {platform_radius * std::cos(a), platform_radius * std::sin(a), -attachment_below_g};
}

// "name" followed by the digit i (a leg's).
std::string numbered(std::string name, int i) {
  name += static_cast<char>('0' + i);
  return name;
}

void build(Model& m, std::string_view) {
  std::array<Expr, 6> length;
  for (int i = 0; i < 6; ++i) length[i] = m.coordinate(numbered("l", i));
  const Expr x = m.implicit_dependent("platform_x", 0), y = m.implicit_dependent("platform_y", 0),
             z = m.implicit_dependent("platform_z", home_height);
  const Expr yaw = m.implicit_dependent("platform_yaw", 0),
             pitch = m.implicit_dependent("platform_pitch", 0),
             roll = m.implicit_dependent("platform_roll", 0);
  m.body("platform")
      .mass(40)
      .inertia(1.3, 1.3, 2.4)
      .motion(Tdisp(x, y, z) * Trotz(yaw) * Troty(pitch) * Trotx(roll));
  for (int i = 0; i < 6; ++i) {
    const Point b = base_joint(i), p = platform_joint(i);
    // The leg's direction u at the home pose: the universal joint's guesses
    // (Rx(a)·Ry(b)·z = (sin b, -sin a·cos b, cos a·cos b) = u) and its length.
    const Point d{p.x - b.x, p.y - b.y, p.z + home_height - b.z};
    const double home_length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    const Expr a = m.implicit_dependent(numbered("a", i), std::atan2(-d.y, d.z));
    const Expr c = m.implicit_dependent(numbered("b", i), std::asin(d.x / home_length));
    m.body(numbered("cylinder", i))
        .mass(3.0)
        .inertia(0.077, 0.077, 0.004)
        .motion(Tdisp(b.x, b.y, b.z) * Trotx(a) * Troty(c) * Tdisp(0, 0, cylinder_g));
    m.body(numbered("piston", i))
        .mass(1.5)
        .inertia(0.032, 0.032, 0.001)
        .relative_to(numbered("cylinder", i))
        .motion(Tdisp(0, 0, length[i] - piston_g - cylinder_g));
    m.close_loop(numbered("leg", i), numbered("piston", i), {0, 0, piston_g}, "platform",
                 {p.x, p.y, p.z});
    m.initial(length[i], home_length);
  }
  m.gravity(0, 0, -9.81);
}

const Registration registration({"stewart", {"default"}, build});

}  // namespace
