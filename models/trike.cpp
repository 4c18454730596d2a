// Three-wheeled vehicle (paper Table 6; docs/models.md 4): 5 bodies, 13 DOF.
// Kinematics and equations of motion only: suspension, steering, drive and
// tyre forces belong to the simulation.
#include <cmath>
#include <numbers>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view) {
  // The chassis' position and attitude, the rear suspension's travel along its
  // strut and the rear axle's roll, the wheels' spins, the steering angle and the
  // front suspension's travel.
  const Expr x = m.coordinate("x"), y = m.coordinate("y"), z = m.coordinate("z");
  const Expr yaw = m.coordinate("yaw"), pitch = m.coordinate("pitch"), roll = m.coordinate("roll");
  const Expr rear_travel = m.coordinate("rear_travel"), axle_roll = m.coordinate("axle_roll");
  const Expr left_spin = m.coordinate("left_spin"), right_spin = m.coordinate("right_spin");
  const Expr steer = m.coordinate("steer"), front_travel = m.coordinate("front_travel"),
             front_spin = m.coordinate("front_spin");
  const double strut = std::numbers::pi / 4;  // the rear strut's inclination
  m.body("chassis")
      .mass(150)
      .inertia(15, 40, 45)
      .motion(Tdisp(x, y, z) * Trotz(yaw) * Troty(pitch) * Trotx(roll));
  m.body("rear_axle")
      .mass(20)
      .inertia(2, 0.2, 2)
      .relative_to("chassis")
      .motion(Tdisp(-0.9 - rear_travel * std::cos(strut), 0, -0.2 + rear_travel * std::sin(strut)) *
              Trotx(axle_roll));
  m.body("left_rear_wheel")
      .mass(5)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("rear_axle")
      .motion(Tdisp(0, 0.55, 0) * Troty(left_spin));
  m.body("right_rear_wheel")
      .mass(5)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("rear_axle")
      .motion(Tdisp(0, -0.55, 0) * Troty(right_spin));
  m.body("front_wheel")
      .mass(6)
      .inertia(0.2, 0.4, 0.2)
      .relative_to("chassis")
      .motion(Tdisp(1.2, 0, -0.2) * Trotz(steer) * Tdisp(0, 0, -front_travel) * Troty(front_spin));
  m.gravity(0, 0, -9.81);
  // Rolling at 5 m/s on wheels of radius 0.3, from 0.5 m high.
  const double speed = 5.0, wheel_radius = 0.3;
  m.initial(x, 0.0, speed);
  m.initial(z, 0.5, 0.0);
  for (const Expr& spin : {left_spin, right_spin, front_spin})
    m.initial(spin, 0.0, speed / wheel_radius);
}

const Registration registration({"trike", {"default"}, build});

}  // namespace
