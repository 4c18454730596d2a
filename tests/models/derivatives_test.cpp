// The emitted derivatives of the inverse dynamics, dtau/dq and dtau/dqd, of
// every reference model and variant at random states: against central
// differences of the emitted inverse_dynamics with Richardson extrapolation
// at two steps (independent of the symbolic engine's calculus), and against
// closed forms written by hand for the double pendulum.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "generated.hpp"
#include "support/model_eval.hpp"
#include "test_plan.hpp"

using namespace symdyn::testing;
namespace gen = symdyn_generated;

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

template <class G>
Eigen::VectorXd inverse_dynamics(const ModelState<double>& s) {
  Eigen::VectorXd tau(G::nq);
  G::inverse_dynamics(s.t, s.q.data(), s.qd.data(), s.qdd.data(), G::param_defaults, tau.data());
  return tau;
}

// d tau / d x_j, x = s.*member: central differences at steps h and h/2 combined
// by Richardson's extrapolation, (4·D(h/2) - D(h))/3: error O(h⁴) + rounding/h.
template <class G>
Eigen::VectorXd richardson_column(const ModelState<double>& s,
                                  std::vector<double> ModelState<double>::*member, int j) {
  const auto central = [&](double h) {
    ModelState<double> plus = s, minus = s;
    (plus.*member)[j] += h;
    (minus.*member)[j] -= h;
    return Eigen::VectorXd((inverse_dynamics<G>(plus) - inverse_dynamics<G>(minus)) / (2 * h));
  };
  const double h = 1e-3 * std::max(1.0, std::abs((s.*member)[j]));
  return (4 * central(h / 2) - central(h)) / 3;
}

template <class G>
void check_derivatives() {
  const TestPlan plan = test_plan(G::model);
  INFO(G::model << " " << G::variant);
  STATIC_REQUIRE(G::has_inverse_dynamics_derivatives);
  std::mt19937 rng(17);
  const int n = G::nq;
  for (int trial = 0; trial < std::max(2, plan.states); ++trial) {
    const ModelState<double> s = random_state_near(rng, G::q_initial, plan.amplitude);
    RowMatrix dq(n, n), dqd(n, n);
    G::inverse_dynamics_derivatives(s.t, s.q.data(), s.qd.data(), s.qdd.data(), G::param_defaults,
                                    dq.data(), dqd.data());
    RowMatrix fq(n, n), fqd(n, n);
    for (int j = 0; j < n; ++j) {
      fq.col(j) = richardson_column<G>(s, &ModelState<double>::q, j);
      fqd.col(j) = richardson_column<G>(s, &ModelState<double>::qd, j);
    }
    const double scale = std::max({1.0, fq.cwiseAbs().maxCoeff(), fqd.cwiseAbs().maxCoeff()});
    INFO("dtau/dq\n"
         << dq << "\ndifferences\n"
         << fq << "\ndtau/dqd\n"
         << dqd << "\ndifferences\n"
         << fqd);
    CHECK((dq - fq).cwiseAbs().maxCoeff() < 1e-7 * scale);
    CHECK((dqd - fqd).cwiseAbs().maxCoeff() < 1e-7 * scale);
  }
}

}  // namespace

TEST_CASE("dtau/dq and dtau/dqd of every reference model match Richardson-extrapolated differences",
          "[models][derivatives]") {
  check_derivatives<gen::double_pendulum_absolute>();
  check_derivatives<gen::double_pendulum_relative>();
  check_derivatives<gen::robot3d_absolute>();
  check_derivatives<gen::robot3d_relative>();
  check_derivatives<gen::slider_crank_inline>();
  check_derivatives<gen::slider_crank_dependent>();
  check_derivatives<gen::trike>();
  check_derivatives<gen::hexapod_tree>();
  check_derivatives<gen::amru5_inline>();
  check_derivatives<gen::amru5_dependent>();
  check_derivatives<gen::chain_2_relative>();
  check_derivatives<gen::chain_2_absolute>();
  check_derivatives<gen::chain_4_relative>();
  check_derivatives<gen::chain_4_absolute>();
  check_derivatives<gen::chain_8_relative>();
  check_derivatives<gen::chain_8_absolute>();
  check_derivatives<gen::chain_16_relative>();
  check_derivatives<gen::chain_16_absolute>();
}

// Two uniform rods (m = 1, l = 1, I_zz = 1/12, G at mid-length), q1 the second's
// angle relative to the first, gravity g along -y:
//   tau1 = (5/3 + cos q1)·qdd0 + (1/3 + cos q1/2)·qdd1 - sin q1·(qd0·qd1 + qd1²/2)
//          + g·(3/2·cos q0 + 1/2·cos(q0 + q1))
//   tau2 = (1/3 + cos q1/2)·qdd0 + qdd1/3 + sin q1·qd0²/2 + g/2·cos(q0 + q1)
TEST_CASE("dtau/dq and dtau/dqd of the double pendulum equal their closed forms",
          "[models][derivatives]") {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    const ModelState<double> s =
        random_state_near(rng, gen::double_pendulum_relative::q_initial, 2.0);
    const double g = 9.81, q0 = s.q[0], q1 = s.q[1], qd0 = s.qd[0], qd1 = s.qd[1];
    const double qdd0 = s.qdd[0], qdd1 = s.qdd[1], c = std::cos(q1), sn = std::sin(q1),
                 s01 = std::sin(q0 + q1);
    const Eigen::Vector2d tau(
        (5.0 / 3 + c) * qdd0 + (1.0 / 3 + c / 2) * qdd1 - sn * (qd0 * qd1 + qd1 * qd1 / 2) +
            g * (1.5 * std::cos(q0) + 0.5 * std::cos(q0 + q1)),
        (1.0 / 3 + c / 2) * qdd0 + qdd1 / 3 + sn * qd0 * qd0 / 2 + g / 2 * std::cos(q0 + q1));
    RowMatrix dq(2, 2), dqd(2, 2);
    dq << -g * (1.5 * std::sin(q0) + 0.5 * s01),
        -sn * qdd0 - sn / 2 * qdd1 - c * (qd0 * qd1 + qd1 * qd1 / 2) - g / 2 * s01,  //
        -g / 2 * s01, -sn / 2 * qdd0 + c * qd0 * qd0 / 2 - g / 2 * s01;
    dqd << -sn * qd1, -sn * (qd0 + qd1),  //
        sn * qd0, 0.0;
    const auto check = [&]<class G>(G) {
      INFO(G::variant);
      CHECK((inverse_dynamics<G>(s) - tau).cwiseAbs().maxCoeff() <
            1e-12);  // the closed form is the model's
      RowMatrix eq(2, 2), eqd(2, 2);
      G::inverse_dynamics_derivatives(s.t, s.q.data(), s.qd.data(), s.qdd.data(), G::param_defaults,
                                      eq.data(), eqd.data());
      CHECK((eq - dq).cwiseAbs().maxCoeff() < 1e-12);
      CHECK((eqd - dqd).cwiseAbs().maxCoeff() < 1e-12);
    };
    check(gen::double_pendulum_absolute{});
    check(gen::double_pendulum_relative{});
  }
}
