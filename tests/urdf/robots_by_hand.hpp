#pragma once
// The robots of tests/urdf/robots/ written by hand with the builder, as a user
// would: absolute motions from the ground, URDF origins as
// Tdisp(xyz)·Rz(yaw)·Ry(pitch)·Rx(roll). Bodies and coordinates in the
// importer's order (depth-first, children by joint name), so that they compare
// body by body.

#include <cmath>
#include <string>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::testing::urdf {

using model::Expr;
using model::Transform;

inline constexpr double kHalfPi = 1.5707963267948966;

inline model::Mat3 tensor(double xx, double xy, double xz, double yy, double yz, double zz) {
  return {Expr(xx), Expr(xy), Expr(xz), Expr(xy), Expr(yy), Expr(yz), Expr(xz), Expr(yz), Expr(zz)};
}

// A URDF <origin>, as a user of the builder writes it: xyz, then Rz(yaw)·Ry(pitch)·Rx(roll).
inline Transform origin(double x, double y, double z, double roll = 0, double pitch = 0,
                        double yaw = 0) {
  return model::Tdisp(x, y, z) * model::Trotz(yaw) * model::Troty(pitch) * model::Trotx(roll);
}

inline model::Model two_link_arm_by_hand() {
  using namespace model;
  Model m("two_link_arm");
  const Expr q1 = m.coordinate("shoulder"), q2 = m.coordinate("elbow");
  m.body("upper_arm")
      .mass(1.5)
      .inertia(0.001, 0.0315, 0.0315)
      .motion(Troty(q1) * Tdisp(0.25, 0, 0));
  m.body("forearm")
      .mass(0.8)
      .inertia(0.0005, 0.011, 0.011)
      .motion(Troty(q1) * Tdisp(0.5, 0, 0) * Troty(q2) * Tdisp(0.2, 0, 0));
  m.gravity(0, 0, -9.81);
  return m;
}

// The arm on a free base: x, y, z, then yaw, pitch, roll of the base link.
inline model::Model floating_two_link_arm_by_hand() {
  using namespace model;
  Model m("two_link_arm");
  std::vector<Expr> b;
  for (const char* s : {"base_link_x", "base_link_y", "base_link_z", "base_link_yaw",
                        "base_link_pitch", "base_link_roll"}) {
    b.push_back(m.coordinate(s));
  }
  const Expr q1 = m.coordinate("shoulder"), q2 = m.coordinate("elbow");
  const Transform base = Tdisp(b[0], b[1], b[2]) * Trotz(b[3]) * Troty(b[4]) * Trotx(b[5]);
  m.body("upper_arm")
      .mass(1.5)
      .inertia(0.001, 0.0315, 0.0315)
      .motion(base * Troty(q1) * Tdisp(0.25, 0, 0));
  m.body("forearm")
      .mass(0.8)
      .inertia(0.0005, 0.011, 0.011)
      .motion(base * Troty(q1) * Tdisp(0.5, 0, 0) * Troty(q2) * Tdisp(0.2, 0, 0));
  m.gravity(0, 0, -9.81);
  return m;
}

inline model::Model mobile_base_by_hand() {
  using namespace model;
  Model m("mobile_base");
  const Expr x = m.coordinate("base_x"), y = m.coordinate("base_y"), yaw = m.coordinate("base_yaw");
  const Expr left = m.coordinate("wheel_left"), right = m.coordinate("wheel_right");
  const Transform chassis_frame = Tdisp(x, y, 0.1) * Trotz(yaw);
  m.body("chassis")
      .mass(12)
      .inertia(tensor(0.3, 0.01, -0.02, 0.5, 0.005, 0.7))
      .motion(chassis_frame * origin(-0.05, 0, 0.05, 0, 0, 0.3));
  m.body("caster")
      .mass(0.2)
      .inertia(0.0001, 0.0001, 0.0001)
      .motion(chassis_frame * Tdisp(-0.25, 0, -0.05));
  m.body("left_wheel")
      .mass(0.5)
      .inertia(0.0015, 0.0015, 0.0025)
      .motion(chassis_frame * origin(0.1, 0.2, 0, -kHalfPi) * Trotz(left));
  m.body("right_wheel")
      .mass(0.5)
      .inertia(0.0015, 0.0025, 0.0015)
      .motion(chassis_frame * Tdisp(0.1, -0.2, 0) * Troty(right));
  m.gravity(0, 0, -9.81);
  return m;
}

inline model::Model six_dof_arm_by_hand() {
  using namespace model;
  Model m("six_dof_arm");
  std::vector<Expr> q;
  for (const char* s : {"joint1", "joint2", "joint3", "joint4", "joint5", "joint6"})
    q.push_back(m.coordinate(s));
  const Transform base = origin(0.1, -0.2, 0.05, 0, 0, 0.4);
  const Transform l1 = base * Tdisp(0, 0, 0.1) * Trotz(q[0]);
  const Transform l2 = l1 * origin(0, 0, 0.2, 0, 0, 0.5) * Troty(q[1]);
  const Transform l3 = l2 * origin(0.4, 0, 0, 0.2) * Trot({Expr(0), Expr(0.6), Expr(0.8)}, q[2]);
  const Transform l4 = l3 * origin(0.3, 0, 0, 0, 0, -0.3) * Trotx(-q[3]);
  const Transform l5 = l4 * origin(0.05, 0, 0, 0.5, 0.1) * Trotz(q[4]);
  const double s = std::sqrt(0.5);
  const Transform l6 = l5 * Tdisp(0.08, 0, 0) * Trot({Expr(s), Expr(s), Expr(0)}, q[5]);
  const Transform grip = l6 * origin(0.05, 0, 0, 0, kHalfPi);
  m.body("base_link").mass(4).inertia(0.02, 0.02, 0.03).motion(base * Tdisp(0, 0, 0.05));
  m.body("link1")
      .mass(3)
      .inertia(tensor(0.02, 0.001, -0.002, 0.03, 0.0015, 0.025))
      .motion(l1 * origin(0, 0.01, 0.1, 0.1, 0.2, 0.3));
  m.body("link2")
      .mass(2.5)
      .inertia(tensor(0.004, -0.0005, 0.0003, 0.04, 0.0002, 0.041))
      .motion(l2 * origin(0.2, 0, 0.02, 0.3, -0.2, 0.1));
  m.body("link3")
      .mass(1.5)
      .inertia(tensor(0.002, 0.0001, 0, 0.012, -0.0003, 0.0125))
      .motion(l3 * origin(0.15, 0.01, 0, 0, 0.25));
  m.body("link5")
      .mass(0.8)
      .inertia(tensor(0.0008, 0.00005, -0.00002, 0.001, 0.00003, 0.0009))
      .motion(l5 * origin(0.04, 0, 0.01, -0.2, 0, 0.4));
  m.body("link6")
      .mass(0.3)
      .inertia(tensor(0.0002, 0, 0.00001, 0.00025, 0, 0.0003))
      .motion(l6 * origin(0.02, 0.01, 0, 0, 0, 0.7));
  m.body("gripper").mass(0.4).inertia(0.0003, 0.0003, 0.0002).motion(grip * Tdisp(0, 0, 0.03));
  m.gravity(0, 0, -9.81);
  return m;
}

}  // namespace symdyn::testing::urdf
