// Three-wheeled vehicle (paper Table 6; docs/models.md 4): 5 bodies, 13 DOF.
// Kinematics and equations of motion only: suspension, steering, drive and
// tyre forces belong to the simulation.
#include <cmath>
#include <numbers>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view) {
  // q0..q2 chassis position, q3..q5 yaw, pitch, roll, q6 rear suspension travel,
  // q7 rear axle roll, q8 q9 rear wheel spins, q10 steering, q11 front
  // suspension travel, q12 front wheel spin.
  const auto q = m.coordinates(13);
  const double strut = std::numbers::pi / 4;  // the rear strut's inclination
  m.body("chassis")
      .mass(150)
      .inertia(15, 40, 45)
      .motion(Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]));
  m.body("rear_axle")
      .mass(20)
      .inertia(2, 0.2, 2)
      .relative_to("chassis")
      .motion(Tdisp(-0.9 - q[6] * std::cos(strut), 0, -0.2 + q[6] * std::sin(strut)) * Trotx(q[7]));
  m.body("left_rear_wheel")
      .mass(5)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("rear_axle")
      .motion(Tdisp(0, 0.55, 0) * Troty(q[8]));
  m.body("right_rear_wheel")
      .mass(5)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("rear_axle")
      .motion(Tdisp(0, -0.55, 0) * Troty(q[9]));
  m.body("front_wheel")
      .mass(6)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("chassis")
      .motion(Tdisp(1.2, 0, -0.2) * Trotz(q[10]) * Tdisp(0, 0, -q[11]) * Troty(q[12]));
  m.gravity(0, 0, -9.81);
  // Rolling at 5 m/s on wheels of radius 0.3, from 0.5 m high.
  const double speed = 5.0, wheel_radius = 0.3;
  m.initial(q[0], 0.0, speed);
  m.initial(q[2], 0.5, 0.0);
  for (int wheel : {8, 9, 12}) m.initial(q[wheel], 0.0, speed / wheel_radius);
}

const Registration registration({"trike", {"default"}, build});

}  // namespace
