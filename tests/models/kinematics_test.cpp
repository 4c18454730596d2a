// The derived kinematics of every reference model and variant (all model files
// are linked in) against independent references (support/kinematics_checks.hpp):
// positions against the direct product of the 4x4 matrices, velocities and
// accelerations against the complex step and central differences along a
// path, partial velocities against velocity differences in qd.
#include <catch2/catch.hpp>

#include "support/kinematics_checks.hpp"
#include "test_plan.hpp"

using namespace symdyn;
using namespace symdyn::testing;

namespace {

States states_for(const model::Model& m, const TestPlan& plan, unsigned seed) {
  std::mt19937 rng(seed);
  States states;
  for (int i = 0; i < plan.states; ++i) states.push_back(random_state_near(rng, m, plan.amplitude));
  return states;
}

// Runs `check` on every reference model and variant, derived without
// simplification and, where the plan says so, with it.
template <class Check>
void for_all_references(unsigned seed, bool partials, Check check) {
  for (const auto& d : model::registry()) {
    const TestPlan plan = test_plan(d.name);
    INFO("model " << d.name);
    REQUIRE(plan.states > 0);
    for (const auto& variant : d.variants) {
      const model::Model m = d.make(variant);
      const States states = states_for(m, plan, seed);
      for (bool simplify : {false, true}) {
        if (simplify && !plan.simplified_derivation) continue;
        INFO(variant << " simplify=" << simplify);
        check(m, derive_for_test(m, simplify, partials), states);
      }
    }
  }
}

}  // namespace

TEST_CASE("reference models: positions equal the direct product of the 4x4 matrices", "[models]") {
  for_all_references(42, false, check_positions_4x4);
}

TEST_CASE("reference models: velocities and accelerations equal the complex step along a path",
          "[models]") {
  for_all_references(7, false, check_complex_step);
}

TEST_CASE("reference models: velocities and accelerations equal central differences along a path",
          "[models]") {
  for_all_references(17, false, check_central_differences);
}

TEST_CASE("reference models: partial velocities equal velocity differences in qd", "[models]") {
  for_all_references(11, true, check_partials_by_qd);
}

TEST_CASE("reference models: the variants of chain_32 and chain_64 agree", "[models]") {
  // chain_N up to 16 is compared through its emitted code (emitted_test.cpp);
  // the bigger ones are generated for benchmarks only, so compare them here.
  for (const char* name : {"chain_32", "chain_64"}) {
    const model::Definition& d = model::find_definition(name);
    const model::Model relative = d.make("relative"), absolute = d.make("absolute");
    INFO(name);
    check_kinematics_agree(relative, derive_for_test(relative, false, true), absolute,
                           derive_for_test(absolute, false, true),
                           states_for(relative, test_plan(name), 5), 1e-10);
  }
}
