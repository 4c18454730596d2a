// Robot with a turret, a telescopic arm and a two-axis wrist (paper Tables 2-3;
// docs/models.md 2): 3 bodies, 5 DOF.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view variant) {
  const Expr yaw = m.coordinate("turret_yaw"), pitch = m.coordinate("arm_pitch"),
             extension = m.coordinate("arm_extension"), wrist_roll = m.coordinate("wrist_roll"),
             wrist_pitch = m.coordinate("wrist_pitch");
  const Expr H = m.parameter("H", 0.5);  // shoulder height
  const Expr L = m.parameter("L", 1.0);  // arm length
  const Expr C = m.parameter("C", 0.2);  // gripper centre offset
  m.body("turret").mass(10.0).inertia(0.3, 0.3, 0.1).motion(Trotz(yaw) * Tdisp(0, 0, H / 2));
  Body& arm = m.body("arm").mass(5.0).inertia(0.01, 0.41666666666666667, 0.41666666666666667);
  Body& gripper = m.body("gripper").mass(2.0).inertia(0.01, 0.02, 0.02);
  const Transform wrist = Trotx(wrist_roll) * Troty(wrist_pitch) * Tdisp(C, 0, 0);
  if (variant == "absolute") {
    const Transform shoulder = Trotz(yaw) * Tdisp(0, 0, H) * Troty(pitch);
    arm.motion(shoulder * Tdisp(extension, 0, 0));
    gripper.motion(shoulder * Tdisp(extension + L / 2, 0, 0) * wrist);
  } else {
    arm.motion(Tdisp(0, 0, H / 2) * Troty(pitch) * Tdisp(extension, 0, 0)).relative_to("turret");
    gripper.motion(Tdisp(L / 2, 0, 0) * wrist).relative_to("arm");
  }
  m.gravity(0, 0, -9.81);
  m.initial(yaw, 0.0, 1.0);
  m.initial(pitch, 0.3);
  m.initial(extension, 0.6);
  m.initial(wrist_roll, 0.0, 2.0);
}

const Registration registration({"robot3d", {"absolute", "relative"}, build});

}  // namespace
