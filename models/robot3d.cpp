// Robot with a turret, a telescopic arm and a two-axis wrist (paper Tables 2-3;
// docs/models.md 2): 3 bodies, 5 DOF.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view variant) {
  // Turret yaw, arm pitch, arm extension, wrist roll, wrist pitch.
  const auto q = m.coordinates(5);
  const Expr H = m.parameter("H", 0.5);  // shoulder height
  const Expr L = m.parameter("L", 1.0);  // arm length
  const Expr C = m.parameter("C", 0.2);  // gripper centre offset
  m.body("turret").mass(10.0).inertia(0.3, 0.3, 0.1).motion(Trotz(q[0]) * Tdisp(0, 0, H / 2));
  Body& arm = m.body("arm").mass(5.0).inertia(0.01, 0.41666666666666667, 0.41666666666666667);
  Body& gripper = m.body("gripper").mass(2.0).inertia(0.01, 0.02, 0.02);
  const Transform wrist = Trotx(q[3]) * Troty(q[4]) * Tdisp(C, 0, 0);
  if (variant == "absolute") {
    const Transform shoulder = Trotz(q[0]) * Tdisp(0, 0, H) * Troty(q[1]);
    arm.motion(shoulder * Tdisp(q[2], 0, 0));
    gripper.motion(shoulder * Tdisp(q[2] + L / 2, 0, 0) * wrist);
  } else {
    arm.motion(Tdisp(0, 0, H / 2) * Troty(q[1]) * Tdisp(q[2], 0, 0)).relative_to("turret");
    gripper.motion(Tdisp(L / 2, 0, 0) * wrist).relative_to("arm");
  }
  m.gravity(0, 0, -9.81);
  const double q_initial[] = {0, 0.3, 0.6, 0, 0};
  const double qd_initial[] = {1.0, 0, 0, 2.0, 0};
  for (std::size_t i = 0; i < q.size(); ++i) m.initial(q[i], q_initial[i], qd_initial[i]);
}

const Registration registration({"robot3d", {"absolute", "relative"}, build});

}  // namespace
