// Derived kinematics against independent references: a direct numerical
// product of the 4x4 matrices (positions), the complex step along a path in
// (q, t) (velocities, accelerations, angular velocities and accelerations),
// and finite differences in qd (partial velocities, exact since v is affine in qd).
#include <catch2/catch.hpp>

#include "support/kinematics_checks.hpp"
#include <symdyn/model/kinematics.hpp>

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;

namespace {

// A body carried by a frame spinning at a prescribed rate about z, with a
// coordinate inside it: accelerations contain every mixed q-t term.
void prescribed(model::Model& m, std::string_view) {
  const auto q = m.coordinates(2);
  const Expr t = m.time();
  m.body("carrier")
      .mass(2.0)
      .inertia(0.1, 0.1, 0.2)
      .motion(model::Trotz(3 * t + sin(t)) * model::Tdisp(0.5, 0, 0));
  m.body("slider")
      .mass(1.0)
      .inertia(0.01, 0.02, 0.02)
      .motion(model::Tdisp(q[0] * t, 0, 0.1) * model::Troty(q[1] + 2 * t) * model::Tdisp(0.2, 0, 0))
      .relative_to("carrier");
  // A rotation about an oblique constant axis (Rodrigues), with a run-time parameter.
  const Expr arm = m.parameter("arm", 0.3, true);
  const model::Vec3 axis{symbolic::rational(1, 3), symbolic::rational(2, 3),
                         symbolic::rational(2, 3)};
  m.body("tilted")
      .mass(0.5)
      .inertia(0.01, 0.01, 0.01)
      .motion(model::Trot(axis, q[0] - q[1]) * model::Tdisp(arm, 0, 0) * model::Trotx(q[1]))
      .relative_to("slider");
}

const model::Registration registration({"prescribed_spin", {"default"}, prescribed});

struct Case {
  std::string model;
  std::string variant;
  bool simplify;
};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const auto& d : model::registry()) {
    for (const auto& v : d.variants) {
      for (bool simplify : {false, true}) cases.push_back({d.name, v, simplify});
    }
  }
  return cases;
}

States random_states(std::mt19937& rng, const model::Model& m, int n) {
  States states;
  for (int i = 0; i < n; ++i) states.push_back(random_state(rng, m.coordinates().size()));
  return states;
}

// Runs `check` on every registered model, variant and simplification setting.
template <class Check>
void for_all_cases(unsigned seed, int n_states, bool partials, Check check) {
  std::mt19937 rng(seed);
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    const model::Kinematics k = derive_for_test(m, c.simplify, partials);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    check(m, k, random_states(rng, m, n_states));
  }
}

}  // namespace

TEST_CASE("positions equal the direct product of the 4x4 matrices", "[kinematics]") {
  for_all_cases(42, 20, false, check_positions_4x4);
}

TEST_CASE("velocities and accelerations equal the complex step of positions along a path",
          "[kinematics]") {
  for_all_cases(7, 10, false, check_complex_step);
}

TEST_CASE("velocities and accelerations equal central differences along a path", "[kinematics]") {
  for_all_cases(17, 5, false, check_central_differences);
}

TEST_CASE("symbolic partial velocities equal velocity differences in qd", "[kinematics]") {
  for_all_cases(11, 5, true, check_partials_by_qd);
}

TEST_CASE("variants of a model agree", "[kinematics]") {
  const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> pairs = {
      {"double_pendulum", {"absolute", "relative"}}, {"slider_crank", {"inline", "dependent"}}};
  std::mt19937 rng(3);
  for (const auto& [name, variants] : pairs) {
    const model::Model a = model::find_definition(name).make(variants.first);
    const model::Model b = model::find_definition(name).make(variants.second);
    INFO(name);
    check_kinematics_agree(a, derive_for_test(a, true, true), b, derive_for_test(b, false, true),
                           random_states(rng, a, 10), 1e-12);
  }
}

TEST_CASE("the angular velocity of the double pendulum's second rod is qd0 + qd1", "[kinematics]") {
  for (const std::string variant : {"absolute", "relative"}) {
    const model::Model m = model::find_definition("double_pendulum").make(variant);
    const model::Kinematics k = derive_for_test(m, true, false);
    const Expr qd0 = m.coordinates()[0].qd;
    const Expr qd1 = m.coordinates()[1].qd;
    INFO(variant);
    CHECK(k.bodies[1].w[0] == Expr(0));
    CHECK(k.bodies[1].w[1] == Expr(0));
    CHECK(k.bodies[1].w[2] == qd0 + qd1);
  }
}

// relative_only: each body's relative motion as in the whole derivation (the
// same interned expressions), and nothing composed.
TEST_CASE("relative_only derives the relative motions alone", "[kinematics]") {
  const auto same = [](const model::Motion& a, const model::Motion& b) {
    return a.R == b.R && a.x == b.x && a.v == b.v && a.w == b.w && a.a == b.a && a.dw == b.dw &&
           a.dv_dqd == b.dv_dqd && a.dw_dqd == b.dw_dqd;
  };
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    model::DeriveOptions options;
    static symbolic::Simplifier simplifier;
    if (c.simplify) options.simplify = [](Expr e) { return simplifier(e); };
    options.symbolic_partials = true;
    const model::Kinematics whole = model::derive_kinematics(m, options);
    options.relative_only = true;
    const model::Kinematics relative = model::derive_kinematics(m, options);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    CHECK(relative.intermediates.empty());
    const std::vector<int> refs = m.reference_indices();
    for (std::size_t i = 0; i < refs.size(); ++i) {
      INFO("body " << m.bodies()[i].name());
      CHECK(same(relative.bodies[i].relative, whole.bodies[i].relative));
      const model::Motion& absolute = relative.bodies[i];
      CHECK(same(absolute, refs[i] < 0 ? relative.bodies[i].relative : model::Motion{}));
    }
  }
}
