// Random multibody systems (support/random_model.hpp, rapidcheck). Every
// derivation, with and without simplification, must match the independent
// references: positions against the 4x4 products, velocities and
// accelerations against the complex step, partial velocities against
// differences in qd, the equations of motion against the direct sums over
// bodies; and the model with its shared motions made relative must move as
// the model as written. A failure prints the smallest model rapidcheck finds
// that still fails.
#include <rapidcheck/catch.h>

#include "support/equations_checks.hpp"
#include "support/random_model.hpp"

using namespace symdyn;
using namespace symdyn::testing;

TEST_CASE("random models match the independent references", "[kinematics][dynamics][random]") {
  rc::prop("kinematics and equations of motion", [] {
    RandomModel random;
    const model::Model m = random.build();
    RC_LOG() << random.description();
    const States states = random_states(m, *rc::gen::arbitrary<unsigned>());
    for (bool simplify : {false, true}) {
      RC_LOG() << "simplify=" << simplify << "\n";
      const model::Kinematics k = derive_for_test(m, simplify, true);
      assert_gap(positions_4x4_gap(m, k, states), 1e-12, "positions");
      assert_gap(complex_step_gap(m, k, states), 1e-10, "velocities and accelerations");
      assert_gap(partials_by_qd_gap(m, k, states), 1e-10, "partial velocities");
      assert_gap(equations_gap(m, k, model::derive_dynamics(m, k), states), 1e-10,
                 "equations of motion");
    }
    const model::Model shared = m.with_shared_motions_relative();
    assert_gap(kinematics_agreement_gap(shared, derive_for_test(shared, true, true), m,
                                        derive_for_test(m, false, true), states),
               1e-10, "shared motions made relative");
  });
}
