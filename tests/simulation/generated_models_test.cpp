// Every generated model with equations of motion (all_models.hpp, from
// SYMDYN_MODELS): the emitted M and h against the ones the runtime assembles
// from the emitted kinematics, at random states near the model's initial one.

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>

#include "all_models.hpp"
#include "runtime/errors.hpp"
#include "runtime/multibody_system.hpp"

namespace {

using namespace symdyn::runtime;

// Small perturbations: the dependent parameters of closed-loop models (amru5's
// acos) are defined only near the assembled configuration.
constexpr double q_spread = 0.2;
constexpr double qd_spread = 2.0;
constexpr int states_per_model = 100;

// A random state near the initial one where the model is defined (closed
// loops: acos within its domain); states where it is not are drawn again.
State random_state(MultibodySystem& system, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    State s = system.model().initial_state();
    s.t = 0.5 * (1.0 + u(rng));
    for (int j = 0; j < system.model().nq(); ++j) {
      s.q(j) += q_spread * u(rng);
      s.qd(j) += qd_spread * u(rng);
    }
    try {
      system.evaluate_kinematics(s);
      return s;
    } catch (const NumericError&) {
    }
  }
  FAIL("model " << system.model().name() << ": no state with finite kinematics near the initial one");
  return {};
}

double max_abs(const Matrix& a) { return a.size() ? a.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

TEMPLATE_LIST_TEST_CASE("emitted M and h equal the assembled ones, and qdd agree", "[models][equations]",
                        symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  INFO("model " << model.name() << " variant " << model.variant());
  REQUIRE(model.has_equations_of_motion());
  MultibodySystem assembled(model, EquationsSource::assembled);
  MultibodySystem emitted(model, EquationsSource::emitted);
  std::mt19937 rng(20240611u + static_cast<unsigned>(model.nq()));
  Matrix Ma, Me;
  Vector ha, he, qdda, qdde, yd;
  for (int k = 0; k < states_per_model; ++k) {
    const State s = random_state(assembled, rng);
    CAPTURE(k, s.t, s.q.transpose(), s.qd.transpose());
    assembled.mass_matrix_assembled(s, Ma);
    emitted.mass_matrix_emitted(s, Me);
    assembled.bias_forces_assembled(s, ha);
    emitted.bias_forces_emitted(s, he);
    CHECK(max_abs(Ma - Me) <= 1e-10 * (1.0 + max_abs(Ma)));
    CHECK(max_abs(ha - he) <= 1e-10 * (1.0 + max_abs(ha)));

    // Independent of both: T = 1/2 qd^T M qd is the kinetic energy of the bodies.
    const double T = emitted.energies(s).kinetic;
    CHECK(std::abs(0.5 * s.qd.dot(Me * s.qd) - T) <= 1e-10 * (1.0 + T));

    assembled.accelerations(s, qdda, yd);
    emitted.accelerations(s, qdde, yd);
    CHECK(max_abs(qdda - qdde) <= 1e-8 * (1.0 + max_abs(qdda)));
  }
}
