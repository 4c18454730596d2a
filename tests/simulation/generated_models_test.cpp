// Every generated model with equations of motion (all_models.hpp, from
// SYMDYN_MODELS): the emitted M and h against the ones the runtime assembles
// from the emitted kinematics, at random states near the model's initial one.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>

#include "all_models.hpp"
#include "random_state.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/relative_motion.hpp>

namespace {

using namespace symdyn::runtime;

constexpr int states_per_model = 100;

using symdyn::testing::max_abs;
using symdyn::testing::random_state;

}  // namespace

TEMPLATE_LIST_TEST_CASE("emitted M and h equal the assembled ones, and qdd agree",
                        "[models][equations]", symdyn_test::all_models) {
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

    // Independent of both: the kinetic energy of the bodies is quadratic in qd with
    // Hessian M, T(qd) = 1/2 qd^T M qd + b^T qd + T(0) (b, T(0) from motions prescribed
    // in t), so that 1/2 (T(qd) + T(-qd)) - T(0) = 1/2 qd^T M qd.
    const auto kinetic = [&](const Vector& qd) {
      State v = s;
      v.qd = qd;
      return emitted.energies(v).kinetic;
    };
    const double T = kinetic(s.qd);
    const double quadratic = 0.5 * (T + kinetic(-s.qd)) - kinetic(Vector::Zero(s.qd.size()));
    CHECK(std::abs(0.5 * s.qd.dot(Me * s.qd) - quadratic) <= 1e-10 * (1.0 + T));

    assembled.accelerations(s, qdda, yd);
    emitted.accelerations(s, qdde, yd);
    CHECK(max_abs(qdda - qdde) <= 1e-8 * (1.0 + max_abs(qdda)));
  }
}

// The recursive forward and inverse dynamics (where emitted) against M and h:
// the same accelerations and residuals through MultibodySystem.
TEMPLATE_LIST_TEST_CASE("the recursive dynamics give the mass matrix's accelerations and residuals",
                        "[models][equations]", symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  INFO("model " << model.name() << " variant " << model.variant());
  MultibodySystem recursive(model), by_matrix(model);
  by_matrix.set_recursive(false);
  CHECK(recursive.recursive() == (model.has_forward_dynamics() || model.has_inverse_dynamics()));
  CHECK_FALSE(by_matrix.recursive());
  std::mt19937 rng(7u + static_cast<unsigned>(model.nq()));
  Vector qdd_r, qdd_m, yd, f_r, f_m, g;
  for (int k = 0; k < 20; ++k) {
    const State s = random_state(recursive, rng);
    CAPTURE(k, s.t, s.q.transpose(), s.qd.transpose());
    recursive.accelerations(s, qdd_r, yd);
    by_matrix.accelerations(s, qdd_m, yd);
    CHECK(max_abs(qdd_r - qdd_m) <= 1e-8 * (1.0 + max_abs(qdd_m)));
    recursive.residual(s, qdd_m, yd, f_r, g);
    by_matrix.residual(s, qdd_m, yd, f_m, g);
    CHECK(max_abs(f_r - f_m) <= 1e-9 * (1.0 + max_abs(f_m)));
  }
}

TEMPLATE_LIST_TEST_CASE(
    "relative motions composed at run time equal the emitted absolute kinematics",
    "[models][relative]", symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  INFO("model " << model.name() << " variant " << model.variant());
  REQUIRE(model.has_relative_accelerations());
  REQUIRE(model.has_relative_partial_velocities());
  MultibodySystem system(model, EquationsSource::emitted);
  std::mt19937 rng(777u + static_cast<unsigned>(model.nq()));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Kinematics emitted = model.make_kinematics(), composed = model.make_kinematics();
  RelativeMotion rel = model.make_relative_motion();
  auto gap = [](const double* a, const double* b, int n) {
    double worst = 0.0, scale = 1.0;
    for (int i = 0; i < n; ++i)
      worst = std::max(worst, std::abs(a[i] - b[i])), scale = std::max(scale, std::abs(b[i]));
    return worst / scale;
  };
  for (int k = 0; k < 20; ++k) {
    const State s = system.extended_state(random_state(system, rng));  // the tree's coordinates
    Vector qdd(model.nq());
    for (int j = 0; j < model.nq(); ++j) qdd(j) = 10.0 * u(rng);
    model.accelerations(s.t, s.q.data(), s.qd.data(), qdd.data(), emitted);
    model.partial_velocities(s.t, s.q.data(), emitted);
    model.relative_accelerations(s.t, s.q.data(), s.qd.data(), qdd.data(), rel);
    model.relative_partial_velocities(s.t, s.q.data(), rel);
    rel.compose(composed, true);
    const int nb = model.nbody(), nq = model.nq();
    CHECK(gap(composed.R_data(), emitted.R_data(), 9 * nb) < 1e-13);
    CHECK(gap(composed.x_data(), emitted.x_data(), 3 * nb) < 1e-13);
    CHECK(gap(composed.v_data(), emitted.v_data(), 3 * nb) < 1e-12);
    CHECK(gap(composed.w_data(), emitted.w_data(), 3 * nb) < 1e-12);
    CHECK(gap(composed.a_data(), emitted.a_data(), 3 * nb) < 1e-11);
    CHECK(gap(composed.dw_data(), emitted.dw_data(), 3 * nb) < 1e-11);
    CHECK(gap(composed.dv_dqd_data(), emitted.dv_dqd_data(), 3 * nb * nq) < 1e-12);
    CHECK(gap(composed.dw_dqd_data(), emitted.dw_dqd_data(), 3 * nb * nq) < 1e-12);
  }
}

TEST_CASE("a relative motion with a cycle or an unknown reference names the body", "[relative]") {
  CHECK_THROWS_WITH(RelativeMotion({-1, 2, 1}, 1), "relative motion: body 1 is relative to itself");
  CHECK_THROWS_WITH(RelativeMotion({-1, 5}, 1),
                    "relative motion: body 1 has reference 5, not a body");
  // Two bodies, the second turned by 90° about z and moved 1 m along the first's x
  // while the first spins at 1 rad/s about z: the second's point moves at 1 m/s along y.
  RelativeMotion rel({-1, 0}, 1);
  const double R0[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, R1[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  std::copy_n(R0, 9, rel.relative().R_data());
  std::copy_n(R1, 9, rel.relative().R_data() + 9);
  rel.relative().w_data()[2] = 1.0;  // body 0
  rel.relative().x_data()[3] = 1.0;  // body 1 at x = 1 in body 0's axes
  Kinematics k(1, 2, 0);
  rel.compose(k, false);
  CHECK(k.x(1).isApprox(Vec3(1, 0, 0)));
  CHECK(k.v(1).isApprox(Vec3(0, 1, 0)));
  CHECK(k.a(1).isApprox(Vec3(-1, 0, 0)));  // centripetal
  CHECK(k.w(1).isApprox(Vec3(0, 0, 1)));
  CHECK(k.R(1).isApprox(Eigen::Map<const RowMat3>(R1)));
}
