// Model::with_shared_motions_relative: which bodies it makes relative, and
// that the kinematics of the rewritten model equal the model's as written.
#include <catch2/catch.hpp>

#include "support/kinematics_checks.hpp"
#include <symdyn/model/kinematics.hpp>

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;
using model::Tdisp;
using model::Trotx;
using model::Troty;
using model::Trotz;

namespace {

// Every body from the ground, sharing prefixes of several kinds: a turret
// (rotating), an arm and a longer forearm on it, a tool sharing the
// forearm's whole motion, a body sharing only a translation, and a body
// relative to the turret whose motion begins with the arm's (another
// reference: not shared).
void shared_prefixes(model::Model& m, std::string_view) {
  const auto q = m.coordinates(5);
  const model::Transform turret = Trotz(q[0]) * Tdisp(0, 0, 0.4);
  const model::Transform arm = turret * Troty(q[1]) * Tdisp(0.3, 0, 0);
  const model::Transform forearm = arm * Tdisp(0.3, 0, 0) * Trotx(q[2]) * Tdisp(0.2, 0.1, 0);
  const model::Transform lift = Tdisp(0, 0, q[3]);
  m.body("turret").mass(4.0).inertia(0.2, 0.2, 0.1).motion(turret);
  m.body("arm").mass(2.0).inertia(0.01, 0.1, 0.1).motion(arm);
  m.body("forearm").mass(1.0).inertia(0.01, 0.05, 0.05).motion(forearm);
  m.body("tool")
      .mass(0.5)
      .inertia(0.01, 0.01, 0.01)
      .motion(forearm * Trotz(q[4]) * Tdisp(0.1, 0, 0));
  m.body("lift").mass(1.0).inertia(0.01, 0.01, 0.01).motion(lift);
  m.body("cart").mass(1.0).inertia(0.02, 0.01, 0.01).motion(lift * Trotz(q[4]) * Tdisp(0.2, 0, 0));
  m.body("on_turret")
      .mass(1.0)
      .inertia(0.01, 0.01, 0.01)
      .motion(arm * Tdisp(0.1, 0, 0))
      .relative_to("turret");
  m.gravity(0, 0, -9.81);
}

const model::Registration registration({"shared_prefixes", {"default"}, shared_prefixes});

std::vector<std::string> references(const model::Model& m) {
  std::vector<std::string> out;
  for (const auto& b : m.bodies()) out.push_back(b.reference().value_or("ground"));
  return out;
}

}  // namespace

TEST_CASE("a body whose motion begins with another's rotating motion moves relative to it",
          "[model]") {
  const model::Model m = model::find_definition("shared_prefixes").make();
  const model::Model shared = m.with_shared_motions_relative();
  CHECK(references(shared) == std::vector<std::string>{"ground", "turret", "arm", "forearm",
                                                       "ground", "ground", "turret"});
  // The rest of the motion is kept: the forearm's last three steps after the arm's four.
  CHECK(shared.bodies()[2].motion().steps().size() == 3);
  CHECK(shared.bodies()[3].motion().steps().size() == 2);
  CHECK(shared.bodies()[5].motion().steps() == m.bodies()[5].motion().steps());
}

TEST_CASE("bodies made relative to a shared motion keep their kinematics", "[model]") {
  std::mt19937 rng(5);
  for (const auto& d : model::registry()) {
    for (const auto& variant : d.variants) {
      const model::Model m = d.make(variant);
      const model::Model shared = m.with_shared_motions_relative();
      INFO(d.name << " " << variant);
      States states;
      for (int i = 0; i < 5; ++i) states.push_back(random_state(rng, m.coordinates().size()));
      check_kinematics_agree(shared, derive_for_test(shared, true, true), m,
                             derive_for_test(m, false, true), states, 1e-12);
    }
  }
}
