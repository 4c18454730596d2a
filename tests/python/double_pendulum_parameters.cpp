// The double pendulum of docs/models.md 1 with its masses and lengths as
// run-time parameters: the Python tests change them and check the mass matrix
// against its closed form.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view) {
  const Expr theta1 = m.coordinate("theta1"), theta2 = m.coordinate("theta2");
  const Expr m1 = m.parameter("m1", 1.0, true), m2 = m.parameter("m2", 1.0, true);
  const Expr l1 = m.parameter("l1", 1.0, true), l2 = m.parameter("l2", 1.0, true);
  // Slender rods along their local x: Iyy = Izz = m l^2 / 12.
  m.body("rod1")
      .mass(m1)
      .inertia(0.001, m1 * l1 * l1 / 12, m1 * l1 * l1 / 12)
      .motion(Trotz(theta1) * Tdisp(l1 / 2, 0, 0));
  m.body("rod2")
      .mass(m2)
      .inertia(0.001, m2 * l2 * l2 / 12, m2 * l2 * l2 / 12)
      .motion(Trotz(theta1) * Tdisp(l1, 0, 0) * Trotz(theta2) * Tdisp(l2 / 2, 0, 0));
  m.gravity(0, -9.81, 0);
}

const Registration registration({"double_pendulum_parameters", {"default"}, build});

}  // namespace
