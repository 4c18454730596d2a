// Double pendulum (paper Table 1; docs/models.md 1): two rods hinged about z.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view variant) {
  const Expr theta1 = m.coordinate("theta1"), theta2 = m.coordinate("theta2");
  const double l1 = 1.0, l2 = 1.0;
  const double Iyy = 0.083333333333333333;
  m.body("rod1").mass(1.0).inertia(0.001, Iyy, Iyy).motion(Trotz(theta1) * Tdisp(l1 / 2, 0, 0));
  Body& rod2 = m.body("rod2").mass(1.0).inertia(0.001, Iyy, Iyy);
  if (variant == "absolute") {
    rod2.motion(Trotz(theta1) * Tdisp(l1, 0, 0) * Trotz(theta2) * Tdisp(l2 / 2, 0, 0));
  } else {
    rod2.motion(Tdisp(l1 / 2, 0, 0) * Trotz(theta2) * Tdisp(l2 / 2, 0, 0)).relative_to("rod1");
  }
  m.gravity(0, -9.81, 0);
}

const Registration registration({"double_pendulum", {"absolute", "relative"}, build});

}  // namespace
