// The models of docs/models.md 1, 2, 6 and 7 as joint trees (mechanism.hpp), each
// step read off the model's T0G products in models/*.cpp.
#include "mechanism.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace symdyn::bench::peers {

namespace {

using Eigen::Vector3d;

const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();

// A massive link: a symdyn body.
Link body(std::string name, int parent, Vector3d p, JointType type, Vector3d axis, int q,
          double mass, Vector3d com, Vector3d inertia, int body_index) {
  Link l;
  l.name = std::move(name);
  l.parent = parent;
  l.p = p;
  l.type = type;
  l.axis = axis;
  l.q = q;
  l.mass = mass;
  l.com = com;
  l.inertia = inertia;
  l.body = body_index;
  return l;
}

// A massless link: one step of a multi-DOF motion.
Link step(std::string name, int parent, Vector3d p, JointType type, Vector3d axis, int q) {
  return body(std::move(name), parent, p, type, axis, q, 0.0, Vector3d::Zero(), Vector3d::Zero(),
              -1);
}

void check(const Mechanism& m) {
  for (int i = 0; i < m.nq(); ++i) {
    const Link& l = m.links[static_cast<std::size_t>(i)];
    if (l.q != i || l.parent >= i)
      throw std::logic_error(m.name + ": link " + l.name + " out of order");
  }
}

}  // namespace

int Mechanism::nbody() const {
  int n = 0;
  for (const Link& l : links) n += l.mass > 0 ? 1 : 0;
  return n;
}

double Mechanism::total_mass() const {
  double m = 0;
  for (const Link& l : links) m += l.mass;
  return m;
}

// rod1: Trotz(q0)·Tdisp(l1/2, 0, 0); rod2: ...·Tdisp(l1, 0, 0)·Trotz(q1)·Tdisp(l2/2, 0, 0).
Mechanism double_pendulum() {
  const Vector3d I(0.001, 0.083333333333333333, 0.083333333333333333);
  Mechanism m{"double_pendulum", {}, Vector3d(0, -9.81, 0)};
  m.links.push_back(body("rod1", -1, Vector3d::Zero(), JointType::revolute, Z, 0, 1.0,
                         Vector3d(0.5, 0, 0), I, 0));
  m.links.push_back(body("rod2", 0, Vector3d(1.0, 0, 0), JointType::revolute, Z, 1, 1.0,
                         Vector3d(0.5, 0, 0), I, 1));
  check(m);
  return m;
}

// turret: Trotz(q0)·Tdisp(0, 0, H/2); arm: Trotz(q0)·Tdisp(0, 0, H)·Troty(q1)·Tdisp(q2, 0, 0);
// gripper: arm's·Tdisp(L/2, 0, 0)·Trotx(q3)·Troty(q4)·Tdisp(C, 0, 0); H = 0.5, L = 1, C = 0.2.
Mechanism robot3d() {
  Mechanism m{"robot3d", {}, Vector3d(0, 0, -9.81)};
  m.links.push_back(body("turret", -1, Vector3d::Zero(), JointType::revolute, Z, 0, 10.0,
                         Vector3d(0, 0, 0.25), Vector3d(0.3, 0.3, 0.1), 0));
  m.links.push_back(step("shoulder", 0, Vector3d(0, 0, 0.5), JointType::revolute, Y, 1));
  m.links.push_back(body("arm", 1, Vector3d::Zero(), JointType::prismatic, X, 2, 5.0,
                         Vector3d::Zero(), Vector3d(0.01, 0.41666666666666667, 0.41666666666666667),
                         1));
  m.links.push_back(step("wrist", 2, Vector3d(0.5, 0, 0), JointType::revolute, X, 3));
  m.links.push_back(body("gripper", 3, Vector3d::Zero(), JointType::revolute, Y, 4, 2.0,
                         Vector3d(0.2, 0, 0), Vector3d(0.01, 0.02, 0.02), 2));
  check(m);
  return m;
}

// Link k: (k == 0 ? 1 : Tdisp(L/2, 0, 0))·Trot_k(q_k)·Tdisp(L/2, 0, 0) from link k-1's
// centre of mass, Trot_k about z, y, x for k mod 3 = 0, 1, 2; L = 0.5.
Mechanism chain(int n) {
  const Vector3d I(0.001, 0.020833333333333333, 0.020833333333333333);
  Mechanism m{"chain_" + std::to_string(n), {}, Vector3d(0, 0, -9.81)};
  const Vector3d axes[] = {Z, Y, X};
  for (int k = 0; k < n; ++k) {
    m.links.push_back(body("link" + std::to_string(k), k - 1,
                           k == 0 ? Vector3d::Zero() : Vector3d(0.5, 0, 0), JointType::revolute,
                           axes[k % 3], k, 1.0, Vector3d(0.25, 0, 0), I, k));
  }
  check(m);
  return m;
}

// body: Tdisp(q0, q1, q2)·Trotz(q3)·Troty(q4)·Trotx(q5); leg k (hip (hx, hy), yaw psi):
// coxa Tdisp(hx, hy, 0)·Trotz(psi + q(6+3k))·Tdisp(0.05, 0, 0) from the body,
// femur Tdisp(0.05, 0, 0)·Troty(q(7+3k))·Tdisp(0.15, 0, 0) from the coxa,
// tibia Tdisp(0.15, 0, 0)·Troty(q(8+3k))·Tdisp(0.2, 0, 0) from the femur.
Mechanism hexapod_tree() {
  Mechanism m{"hexapod_tree", {}, Vector3d(0, 0, -9.81)};
  const auto P = JointType::prismatic, R = JointType::revolute;
  m.links.push_back(step("base_x", -1, Vector3d::Zero(), P, X, 0));
  m.links.push_back(step("base_y", 0, Vector3d::Zero(), P, Y, 1));
  m.links.push_back(step("base_z", 1, Vector3d::Zero(), P, Z, 2));
  m.links.push_back(step("base_yaw", 2, Vector3d::Zero(), R, Z, 3));
  m.links.push_back(step("base_pitch", 3, Vector3d::Zero(), R, Y, 4));
  m.links.push_back(body("body", 4, Vector3d::Zero(), R, X, 5, 60.0, Vector3d::Zero(),
                         Vector3d(2.0, 7.4, 9.0), 0));
  const double hips[6][2] = {{0.5, 0.3},  {0.5, -0.3}, {0.0, 0.3},
                             {0.0, -0.3}, {-0.5, 0.3}, {-0.5, -0.3}};
  for (int k = 0; k < 6; ++k) {
    const std::string s = std::to_string(k);
    const double psi = hips[k][1] > 0 ? std::numbers::pi / 2 : -std::numbers::pi / 2;
    const int coxa = m.nq();
    Link c = body("coxa_" + s, 5, Vector3d(hips[k][0], hips[k][1], 0), R, Z, coxa, 1.0,
                  Vector3d(0.05, 0, 0), Vector3d(0.002, 0.002, 0.002), 1 + 3 * k);
    c.R = Eigen::AngleAxisd(psi, Vector3d::UnitZ()).toRotationMatrix();
    m.links.push_back(c);
    m.links.push_back(body("femur_" + s, coxa, Vector3d(0.1, 0, 0), R, Y, coxa + 1, 2.0,
                           Vector3d(0.15, 0, 0), Vector3d(0.002, 0.015, 0.015), 2 + 3 * k));
    m.links.push_back(body("tibia_" + s, coxa + 1, Vector3d(0.3, 0, 0), R, Y, coxa + 2, 2.0,
                           Vector3d(0.2, 0, 0), Vector3d(0.002, 0.03, 0.03), 3 + 3 * k));
  }
  check(m);
  return m;
}

// chassis: Tdisp(q0, q1, q2)·Trotz(q3)·Troty(q4)·Trotx(q5); rear axle from the chassis:
// Tdisp(-0.9 - q6·cos(pi/4), 0, -0.2 + q6·sin(pi/4))·Trotx(q7) (a slider along the
// inclined strut); rear wheels from the axle: Tdisp(0, ±0.55, 0)·Troty(q8 | q9); front
// wheel from the chassis: Tdisp(1.2, 0, -0.2)·Trotz(q10)·Tdisp(0, 0, -q11)·Troty(q12).
// The multibody system only: its tyre, suspension, steering and drive forces are not here.
Mechanism trike() {
  Mechanism m{"trike", {}, Vector3d(0, 0, -9.81)};
  const auto P = JointType::prismatic, R = JointType::revolute;
  const double strut = std::numbers::pi / 4;
  m.links.push_back(step("base_x", -1, Vector3d::Zero(), P, X, 0));
  m.links.push_back(step("base_y", 0, Vector3d::Zero(), P, Y, 1));
  m.links.push_back(step("base_z", 1, Vector3d::Zero(), P, Z, 2));
  m.links.push_back(step("base_yaw", 2, Vector3d::Zero(), R, Z, 3));
  m.links.push_back(step("base_pitch", 3, Vector3d::Zero(), R, Y, 4));
  m.links.push_back(body("chassis", 4, Vector3d::Zero(), R, X, 5, 150.0, Vector3d::Zero(),
                         Vector3d(15, 40, 45), 0));
  m.links.push_back(step("rear_strut", 5, Vector3d(-0.9, 0, -0.2), P,
                         Vector3d(-std::cos(strut), 0, std::sin(strut)), 6));
  m.links.push_back(body("rear_axle", 6, Vector3d::Zero(), R, X, 7, 20.0, Vector3d::Zero(),
                         Vector3d(2, 0.2, 2), 1));
  m.links.push_back(body("left_rear_wheel", 7, Vector3d(0, 0.55, 0), R, Y, 8, 5.0, Vector3d::Zero(),
                         Vector3d(0.2, 0.4, 0.2), 2));
  m.links.push_back(body("right_rear_wheel", 7, Vector3d(0, -0.55, 0), R, Y, 9, 5.0,
                         Vector3d::Zero(), Vector3d(0.2, 0.4, 0.2), 3));
  m.links.push_back(step("steering", 5, Vector3d(1.2, 0, -0.2), R, Z, 10));
  m.links.push_back(step("front_suspension", 10, Vector3d::Zero(), P, -Z, 11));
  m.links.push_back(body("front_wheel", 11, Vector3d::Zero(), R, Y, 12, 6.0, Vector3d::Zero(),
                         Vector3d(0.2, 0.4, 0.2), 4));
  check(m);
  return m;
}

}  // namespace symdyn::bench::peers
