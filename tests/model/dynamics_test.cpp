// The equations of motion (composite inertias about each tree's point O,
// model/dynamics.hpp) against the direct sums over bodies, evaluated
// numerically from the kinematics' partial velocities (equations_checks.hpp),
// on every registered model, and on a floating tree with full inertia tensors,
// shared and dependent coordinates, a body driven by a dependent parameter
// alone (one twist direction for two coordinates), a body turned by one angle
// of three coordinates and time (one screw), a body alone, and its base far
// from the origin.
#include <catch2/catch.hpp>

#include "support/equations_checks.hpp"

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;

namespace {

model::Mat3 tensor(double xx, double yy, double zz, double xy, double xz, double yz) {
  return {Expr(xx), Expr(xy), Expr(xz), Expr(xy), Expr(yy), Expr(yz), Expr(xz), Expr(yz), Expr(zz)};
}

void floating_tree(model::Model& m, std::string_view) {
  using namespace symdyn::model;
  const auto q = m.coordinates(9);
  const Expr p = m.dependent("p", 0.2 + 0.1 * sin(q[6] - q[7]));
  m.body("base")
      .mass(3.0)
      .inertia(tensor(0.4, 0.5, 0.6, 0.05, -0.02, 0.03))
      .motion(Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]));
  m.body("arm")
      .mass(1.2)
      .inertia(tensor(0.02, 0.09, 0.1, 0.004, 0.001, -0.003))
      .relative_to("base")
      .motion(Tdisp(0.3, 0.1, -0.2) * Troty(q[6]) * Tdisp(0.4, 0, 0));
  m.body("hand")
      .mass(0.4)
      .inertia(0.001, 0.01, 0.01)
      .relative_to("arm")  // a rod: one repeated moment
      .motion(Trotx(q[7]) * Tdisp(q[8], 0, 0.1));
  m.body("ball")
      .mass(0.7)
      .inertia(0.003, 0.003, 0.003)
      .relative_to("base")  // coordinates shared with arm
      .motion(Trotz(q[6] + q[7]) * Tdisp(p, 0, 0.05));
  m.body("slider")
      .mass(0.3)
      .inertia(0.002, 0.004, 0.005)
      .relative_to("arm")  // driven by p alone
      .motion(Tdisp(p, 0, 0.05) * Troty(2 * p));
  m.body("link")
      .mass(0.5)
      .inertia(tensor(0.004, 0.006, 0.007, 0.001, 0.0005, -0.001))
      .relative_to("arm")
      .motion(Tdisp(0.1, 0.05, 0) * Troty(p - q[8] + 0.5 * m.time()) *
              Tdisp(0.2, 0, 0));  // one screw, 3 coordinates
  m.body("alone")
      .mass(0.9)
      .inertia(0.01, 0.02, 0.03)
      .motion(Trotz(q[7]) * Tdisp(1, 0, 0) * Trotx(q[5]));
  m.gravity(0, 0, -9.81);
}

const model::Registration registration({"floating_tree", {"default"}, floating_tree});

void check_equations(const std::string& name, const std::string& variant, double position_scale) {
  const model::Model m = model::find_definition(name).make(variant);
  std::mt19937 rng(5);
  for (bool simplify : {false, true}) {
    const model::Kinematics k = derive_for_test(m, simplify, true);
    const model::Dynamics d = model::derive_dynamics(m, k);
    States states;
    for (int trial = 0; trial < 5; ++trial) {
      states.push_back(random_state(rng, m.coordinates().size()));
      if (name == "floating_tree") {
        for (int c = 0; c < 3; ++c) states.back().q[c] *= position_scale;
      }
    }
    INFO(name << " " << variant << " simplify=" << simplify << " base at " << position_scale);
    check_gap(equations_gap(m, k, d, states), 1e-12);
  }
}

}  // namespace

TEST_CASE("equations of motion by composite inertias equal the direct sums over bodies",
          "[dynamics]") {
  for (const auto& definition : model::registry()) {
    for (const auto& variant : definition.variants) check_equations(definition.name, variant, 1.0);
  }
}

TEST_CASE("the equations of motion stay accurate with the floating base far from the origin",
          "[dynamics]") {
  check_equations("floating_tree", "default", 1e4);
}
