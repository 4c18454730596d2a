// The exact Jacobians of the runtime (MultibodySystem::jacobians and
// dynamics_derivatives from the emitted inverse_dynamics_derivatives) against
// differences of the residual and of the accelerations with Richardson's
// extrapolation, on every generated model that has them, with force elements;
// and the double pendulum's modes against their closed forms.

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <unsupported/Eigen/Polynomials>

#include "all_models.hpp"
#include "random_state.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>
#include <symdyn/runtime/step_derivatives.hpp>

namespace {

using namespace symdyn::runtime;

using symdyn::testing::max_abs;
using symdyn::testing::random_state;

// d g(x)/d x_j of a vector function of one component, by central differences
// at h and h/2 combined by Richardson's extrapolation: error O(h⁴) + rounding/h.
// h = 1e-4: amru5's legs near a stretched knee (acos near 1) have K ~ 1e6, whose
// fifth derivatives make 1e-3 too coarse.
template <class F>
Vector richardson(F g, double x, double scale) {
  const double h = 1e-4 * std::max(1.0, std::abs(x)) * scale;
  const auto central = [&](double step) -> Vector {
    return (g(x + step) - g(x - step)) / (2 * step);
  };
  return (4 * central(h / 2) - central(h)) / 3;
}

// K = df/dq and C = df/dqd of the residual at (s, qdd), by Richardson's differences.
void residual_jacobians_by_differences(MultibodySystem& system, const State& s, const Vector& qdd,
                                       Matrix& C, Matrix& K) {
  const int n = system.num_coordinates();
  C.resize(n, n);
  K.resize(n, n);
  const Vector yd = Vector::Zero(system.num_extra_states());
  for (int j = 0; j < n; ++j) {
    const auto f_of = [&](Vector State::*member) {
      return [&, member](double x) {
        State p = s;
        (p.*member)(j) = x;
        Vector f, g;
        system.residual(p, qdd, yd, f, g);
        return f;
      };
    };
    K.col(j) = richardson(f_of(&State::q), s.q(j), 1.0);
    C.col(j) = richardson(f_of(&State::qd), s.qd(j), 1.0);
  }
}

// A spring-damper on every coordinate; on the first body a point spring-damper
// to the ground, on the last one a constant load, between the two a spring
// (exact with the kinematics' derivatives); a user force (differenced).
void add_force_elements(MultibodySystem& system) {
  for (int j = 0; j < system.model().nq(); ++j) {
    system.add<CoordinateSpringDamper>(fmt::format("c{}", j), j, 3.0 + j, 0.5 + 0.1 * j);
  }
  const int last = system.model().nbody() - 1;
  system.add<PointLoad>("push", BodyPoint{last, Vec3(0.05, -0.1, 0.2)}, Vec3(3.0, -2.0, 1.0),
                        Vec3(0.5, 0.2, -0.3));
  if (last > 0) {
    system.add<PointSpringDamper>("link", BodyPoint{0, Vec3(0.0, 0.1, 0.0)},
                                  BodyPoint{last, Vec3(0.1, 0.0, 0.05)}, 50.0, 0.2, 0.7);
  }
  system.add<UserForce>(
      "drag",
      [](const State& s, const Kinematics&, Loads& loads) {
        loads.add_generalized(0, -0.3 * s.qd(0) * std::abs(s.qd(0)));
      },
      KinematicsLevel::none);
  system.add<PointSpringDamper>("strut", BodyPoint{0, Vec3(0.1, 0.0, 0.0)},
                                BodyPoint{ground, Vec3(0.0, 1.0, 0.5)}, 200.0, 3.0, 0.4);
}

}  // namespace

TEMPLATE_LIST_TEST_CASE("exact C and K equal Richardson differences of the residual",
                        "[models][derivatives]", symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  if (!model.has_inverse_dynamics_derivatives()) return;
  INFO("model " << model.name() << " variant " << model.variant());
  std::mt19937 rng(99);
  for (bool with_elements : {false, true}) {
    MultibodySystem system(model);
    if (with_elements) add_force_elements(system);
    REQUIRE(system.exact_jacobians());
    for (int trial = 0; trial < 2; ++trial) {
      const State s = random_state(system, rng);
      Vector qdd, yd;
      system.accelerations(s, qdd, yd);
      Matrix M, C, K, Cd, Kd;
      system.jacobians(s, qdd, M, C, K);
      residual_jacobians_by_differences(system, s, qdd, Cd, Kd);
      const double scale = std::max({1.0, max_abs(Kd), max_abs(Cd)});
      INFO("with force elements " << with_elements << "\nK\n" << K << "\ndifferences\n" << Kd);
      CHECK(max_abs(K - Kd) < 1e-7 * scale);
      CHECK(max_abs(C - Cd) < 1e-7 * scale);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("dynamics_derivatives equal Richardson differences of the accelerations",
                        "[models][derivatives]", symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  if (!model.has_inverse_dynamics_derivatives() || model.nq() > 20) return;
  INFO("model " << model.name() << " variant " << model.variant());
  MultibodySystem system(model);
  add_force_elements(system);
  std::mt19937 rng(7);
  const State s = random_state(system, rng);
  DynamicsDerivatives d;
  system.dynamics_derivatives(s, d, true);
  const int n = model.nq();
  Matrix dq(n, n), dqd(n, n);
  for (int j = 0; j < n; ++j) {
    const auto qdd_of = [&](Vector State::*member) {
      return [&, member](double x) {
        State p = s;
        (p.*member)(j) = x;
        Vector qdd, yd;
        system.accelerations(p, qdd, yd);
        return qdd;
      };
    };
    dq.col(j) = richardson(qdd_of(&State::q), s.q(j), 1.0);
    dqd.col(j) = richardson(qdd_of(&State::qd), s.qd(j), 1.0);
  }
  const double scale = std::max({1.0, max_abs(dq), max_abs(dqd)});
  CHECK(max_abs(d.dqdd_dq - dq) < 1e-6 * scale);
  CHECK(max_abs(d.dqdd_dqd - dqd) < 1e-6 * scale);
  // dqdd/dtau = M⁻¹: M·M⁻¹ = I.
  Matrix M;
  system.mass_matrix(s, M);
  CHECK(max_abs(M * d.dqdd_dtau - Matrix::Identity(n, n)) < 1e-9 * std::max(1.0, max_abs(M)));
}

TEST_CASE("set_exact_jacobians(false) differences the residual as a model without derivatives",
          "[models][derivatives]") {
  MultibodySystem system(Model::from<symdyn_generated::robot3d_absolute>());
  add_force_elements(system);
  REQUIRE(system.exact_jacobians());
  std::mt19937 rng(3);
  const State s = random_state(system, rng);
  DynamicsDerivatives exact, differenced;
  system.dynamics_derivatives(s, exact, true);
  Matrix dq, dqd;
  CHECK(system.exact_acceleration_derivatives(s, exact.qdd, dq, dqd));
  system.set_exact_jacobians(false);
  CHECK_FALSE(system.exact_jacobians());
  CHECK(system.jacobian_method() == "central differences of the residual");
  CHECK_FALSE(system.exact_acceleration_derivatives(s, exact.qdd, dq, dqd));
  system.dynamics_derivatives(s, differenced, true);
  const double scale = std::max({1.0, max_abs(exact.dqdd_dq), max_abs(exact.dqdd_dqd)});
  CHECK(max_abs(differenced.dqdd_dq - exact.dqdd_dq) < 1e-6 * scale);
  CHECK(max_abs(differenced.dqdd_dqd - exact.dqdd_dqd) < 1e-6 * scale);
  CHECK(max_abs(differenced.dqdd_dtau - exact.dqdd_dtau) < 1e-12 * max_abs(exact.dqdd_dtau));
  system.set_exact_jacobians(true);
  CHECK(system.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for user force 'drag'");
}

TEST_CASE("the double pendulum's modes are omega² = g·(3 ∓ 6/√7) to rounding",
          "[models][derivatives]") {
  // Two uniform rods of mass 1 and length 1 hanging: in the angles from the
  // vertical, M = [4/3 1/2; 1/2 1/3], K = g·[3/2 0; 0 1/2], hence
  // det(K - ω²M) = 0 gives ω⁴ - 6gω² + 27g²/7 = 0.
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
  REQUIRE(system.exact_jacobians());
  State s = system.initial_state();
  s.q << -std::numbers::pi / 2, 0.0;
  const Linearization lin = linearize(system, s);
  const std::vector<Mode> ms = modes(lin);
  REQUIRE(ms.size() == 2);
  const double g = 9.81;
  const double expected[2] = {std::sqrt(g * (3 - 6 / std::sqrt(7.0))),
                              std::sqrt(g * (3 + 6 / std::sqrt(7.0)))};
  for (int m = 0; m < 2; ++m) {
    const double omega = 2 * std::numbers::pi * ms[m].natural_frequency_hz;
    CHECK(std::abs(omega - expected[m]) < 1e-13 * expected[m]);
    CHECK(std::abs(ms[m].damping_ratio) < 1e-15);
  }
}

TEST_CASE("the damped double pendulum's poles are the roots of det(λ²M + λC + K)",
          "[models][derivatives]") {
  // Dampers c0, c1 on the two joints (relative angles q0, q1): C = diag(c0, c1)
  // in these coordinates; with M and K in closed form (relative angles from
  // the horizontal, hanging at q0 = -π/2), det(λ²M + λC + K) is a quartic in λ
  // whose roots are the poles.
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_relative>());
  const double c0 = 0.3, c1 = 0.1, g = 9.81;
  system.add<CoordinateSpringDamper>("hip", 0, 0.0, c0);
  system.add<CoordinateSpringDamper>("knee", 1, 0.0, c1);
  REQUIRE(system.jacobian_method() == "exact (emitted derivatives)");
  State s = system.initial_state();
  s.q << -std::numbers::pi / 2, 0.0;
  const Linearization lin = linearize(system, s);
  Eigen::Matrix2d M, K;
  M << 8.0 / 3, 5.0 / 6, 5.0 / 6, 1.0 / 3;
  K << 2 * g, g / 2, g / 2, g / 2;
  CHECK(max_abs(lin.M - M) < 1e-14);
  CHECK(max_abs(lin.K - K) < 1e-13);
  // det([a0 + a1 λ + a2 λ², ...]) coefficients by hand: entries e_ij(λ) = K_ij + C_ij λ + M_ij λ².
  const auto poly = [&](int i, int j) {
    return Eigen::Vector3d(K(i, j), i == j ? (i == 0 ? c0 : c1) : 0.0, M(i, j));
  };
  const auto product = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Eigen::Matrix<double, 5, 1> p = Eigen::Matrix<double, 5, 1>::Zero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) p(i + j) += a(i) * b(j);
    }
    return p;
  };
  const Eigen::Matrix<double, 5, 1> det =
      product(poly(0, 0), poly(1, 1)) - product(poly(0, 1), poly(1, 0));
  Eigen::PolynomialSolver<double, 4> solver(det);
  std::vector<std::complex<double>> roots(solver.roots().begin(), solver.roots().end());
  const std::vector<Mode> ms = modes(lin);
  REQUIRE(ms.size() == 2);
  for (const Mode& mode : ms) {
    const auto nearest = *std::min_element(roots.begin(), roots.end(), [&](auto a, auto b) {
      return std::abs(a - mode.pole) < std::abs(b - mode.pole);
    });
    INFO("pole " << mode.pole << ", root " << nearest);
    CHECK(std::abs(nearest - mode.pole) < 1e-12 * std::abs(nearest));
    CHECK(std::abs(mode.damping_ratio - (-nearest.real() / std::abs(nearest))) < 1e-12);
  }
}

TEST_CASE("jacobian_method names the force elements differenced", "[models][derivatives]") {
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  system.add<CoordinateSpringDamper>("hip", 0, 1.0, 0.1);
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  system.add<PointSpringDamper>("strut", BodyPoint{1, Vec3(0.5, 0.0, 0.0)},
                                BodyPoint{ground, Vec3(0.0, 1.0, 0.0)}, 10.0, 1.0, 0.1);
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  system.add<PointLoad>(
      "wind", BodyPoint{1, Vec3::Zero()},
      [](const State&, const Kinematics&, Vec3& f, Vec3&) { f = Vec3(1.0, 0.0, 0.0); });
  CHECK(system.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for load 'wind'");
  MultibodySystem assembled(Model::from<symdyn_generated::double_pendulum_absolute>(),
                            EquationsSource::assembled);
  CHECK(assembled.jacobian_method() == "central differences of the residual");
}

TEST_CASE(
    "one rk4 step and its derivatives: the integrator's step, and Richardson differences of it",
    "[models][derivatives]") {
  MultibodySystem system(Model::from<symdyn_generated::slider_crank_dependent>());
  system.add<CoordinateSpringDamper>("crank", 0, 5.0, 0.2);
  State s = system.initial_state();
  s.t = 0.3;
  s.q(0) = 0.7;
  s.qd(0) = 4.0;
  Vector u(1);
  u << 1.5;
  const double h = 0.01;
  StepDerivatives d;
  rk4_step_derivatives(system, s, u, h, d);
  // The rk4 integrator's step from the same state, u as a constant coordinate force.
  MultibodySystem driven(Model::from<symdyn_generated::slider_crank_dependent>());
  driven.add<CoordinateSpringDamper>("crank", 0, 5.0, 0.2);
  driven.add<CoordinateForce>("u", 0, [&](double, double, double, const State&) { return u(0); });
  IntegratorOptions options;
  options.initial_step = h;
  const State one = make_integrator("rk4", options)->integrate(driven, s, s.t + h);
  CHECK(std::abs(one.q(0) - d.next.q(0)) < 1e-15 * std::max(1.0, std::abs(one.q(0))));
  CHECK(std::abs(one.qd(0) - d.next.qd(0)) < 1e-14 * std::max(1.0, std::abs(one.qd(0))));
  // Richardson differences of the step's end state.
  const auto next = [&](const State& from, const Vector& input) {
    StepDerivatives e;
    rk4_step_derivatives(system, from, input, h, e);
    Vector x(2);
    x << e.next.q(0), e.next.qd(0);
    return x;
  };
  const auto of_q = [&](double x) {
    State p = s;
    p.q(0) = x;
    return next(p, u);
  };
  const auto of_qd = [&](double x) {
    State p = s;
    p.qd(0) = x;
    return next(p, u);
  };
  const auto of_u = [&](double x) {
    Vector v(1);
    v << x;
    return next(s, v);
  };
  Matrix A(2, 2), B(2, 1);
  A.col(0) = richardson(of_q, s.q(0), 1.0);
  A.col(1) = richardson(of_qd, s.qd(0), 1.0);
  B.col(0) = richardson(of_u, u(0), 1.0);
  INFO("A\n" << d.A << "\ndifferences\n" << A << "\nB\n" << d.B << "\ndifferences\n" << B);
  CHECK(max_abs(d.A - A) < 1e-9 * std::max(1.0, max_abs(A)));
  CHECK(max_abs(d.B - B) < 1e-9 * std::max(1.0, max_abs(B)));
}
