// The exact Jacobians of the runtime (MultibodySystem::jacobians and
// dynamics_derivatives from the emitted inverse_dynamics_derivatives) against
// differences of the residual and of the accelerations with Richardson's
// extrapolation, on every generated model that has them, with force elements
// (and the emitted inverse_dynamics_jacobians against the separate entry points);
// the exact derivatives of the bushing, contact and tyres in each regime of
// their laws against Richardson differences of their generalized forces, and so
// the derivatives given with coordinate forces' and user forces' laws (a wrong one
// caught, one resized or not finite refused, Newmark with and without them); and
// the double pendulum's modes against their closed forms.

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <unsupported/Eigen/Polynomials>

#include "all_models.hpp"
#include "differences.hpp"
#include "random_state.hpp"
#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/gim_tyre.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>
#include <symdyn/runtime/relative_motion.hpp>
#include <symdyn/runtime/step_derivatives.hpp>

namespace {

using namespace symdyn::runtime;

using symdyn::testing::max_abs;
using symdyn::testing::random_state;

// d g(x)/d x_j by symdyn::testing::richardson at h = 1e-4·max(1, |x|)·scale:
// amru5's legs near a stretched knee (acos near 1) have K ~ 1e6, whose fifth
// derivatives make 1e-3 too coarse.
template <class F>
Vector richardson_relative(F g, double x, double scale) {
  return symdyn::testing::richardson(g, x, 1e-4 * std::max(1.0, std::abs(x)) * scale);
}

// K = df/dq and C = df/dqd of the residual at (s, qdd), by Richardson's differences.
void residual_jacobians_by_differences(MultibodySystem& system, const State& s, const Vector& qdd,
                                       Matrix& C, Matrix& K) {
  symdyn::testing::residual_jacobians_by_differences(
      system, s, qdd, C, K, [](double x) { return 1e-4 * std::max(1.0, std::abs(x)); });
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

// The elements' exact dQ/dq and dQ/dqd (K and C of the bare model less those of the
// model with them: f = tau - Q) against Richardson differences of their generalized
// forces, the steps scaled by `step` (below 1 at states near a switch of a law, so that
// the differences stay on its side).
// The largest differences between the exact dQ/dq, dQ/dqd and Richardson's, and the
// largest of these differences (at least 1), to scale them.
struct LoadDerivativeErrors {
  double dq = 0.0, dqd = 0.0, scale = 1.0;
};

LoadDerivativeErrors load_derivative_errors(MultibodySystem& with, MultibodySystem& bare,
                                            const State& s, double step = 1.0) {
  const int n = with.num_coordinates();
  const Vector zero = Vector::Zero(n);
  Matrix M, C, K, Cb, Kb;
  with.jacobians(s, zero, M, C, K);
  bare.jacobians(s, zero, M, Cb, Kb);
  const Matrix dQ_dq = Kb - K, dQ_dqd = Cb - C;
  Matrix Dq(n, n), Dqd(n, n);
  for (int j = 0; j < n; ++j) {
    const auto Q_of = [&](Vector State::*member) {
      return [&, member](double x) {
        State p = s;
        (p.*member)(j) = x;
        Vector Q;
        with.applied_forces(p, Q);
        return Q;
      };
    };
    Dq.col(j) = richardson_relative(Q_of(&State::q), s.q(j), step);
    Dqd.col(j) = richardson_relative(Q_of(&State::qd), s.qd(j), step);
  }
  UNSCOPED_INFO("dQ/dq\n"
                << dQ_dq << "\ndifferences\n"
                << Dq << "\ndQ/dqd\n"
                << dQ_dqd << "\ndifferences\n"
                << Dqd);
  return {max_abs(dQ_dq - Dq), max_abs(dQ_dqd - Dqd), std::max({1.0, max_abs(Dq), max_abs(Dqd)})};
}

void check_load_derivatives(MultibodySystem& with, MultibodySystem& bare, const State& s,
                            double step = 1.0) {
  REQUIRE(with.jacobian_method() == "exact (emitted derivatives)");
  const LoadDerivativeErrors e = load_derivative_errors(with, bare, s, step);
  CHECK(e.dq < 1e-7 * e.scale);
  CHECK(e.dqd < 1e-7 * e.scale);
}

// robot3d (turret, arm, gripper; 5 coordinates) at a random state, bare and with the
// element under test.
struct Rig {
  MultibodySystem bare{Model::from<symdyn_generated::robot3d_absolute>()};
  MultibodySystem with{Model::from<symdyn_generated::robot3d_absolute>()};
  State s;
  explicit Rig(std::mt19937& rng) : s(random_state(bare, rng)) {}
  const Kinematics& kinematics() { return bare.evaluate_kinematics(s); }
  // Velocities scaled (the model is scleronomic: v and w are linear in qd).
  void scale_speeds(double factor) { s.qd *= factor; }
};

constexpr int gripper = 2;
const Vec3 tilted_normal = Vec3(0.2, -0.3, 1.0).normalized();

// The plane of normal n placing the element's contact point `lowest` at penetration pen.
Plane plane_at(const Vec3& lowest, const Vec3& n, double pen) {
  return {lowest + pen * n, n};
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
      // M from the derivatives' call (inverse_dynamics_jacobians) is mass_matrix's.
      Matrix Mm;
      system.mass_matrix(s, Mm);
      CHECK(max_abs(M - Mm) < 1e-12 * std::max(1.0, max_abs(Mm)));
    }
  }
}

TEMPLATE_LIST_TEST_CASE(
    "inverse_dynamics_jacobians gives inverse_dynamics_derivatives' K and C and mass_matrix's M",
    "[models][derivatives]", symdyn_test::all_models) {
  const Model model = Model::from<TestType>();
  if (!model.has_inverse_dynamics_derivatives()) return;
  INFO("model " << model.name() << " variant " << model.variant());
  REQUIRE(model.has_inverse_dynamics_jacobians());
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = model.nq();  // all coordinates, the loops' dependent ones too
  for (int trial = 0; trial < 3; ++trial) {
    State s = model.initial_state();
    Vector qdd(n);
    for (int j = 0; j < n; ++j) s.q(j) += 0.1 * u(rng), s.qd(j) = u(rng), qdd(j) = u(rng);
    Matrix K, C, M, Kd, Cd, Mm(n, n);
    model.inverse_dynamics_jacobians(s.t, s.q.data(), s.qd.data(), qdd.data(), K, C, M);
    model.inverse_dynamics_derivatives(s.t, s.q.data(), s.qd.data(), qdd.data(), Kd, Cd);
    model.mass_matrix(s.t, s.q.data(), Mm.data());
    const double scale = std::max({1.0, max_abs(Kd), max_abs(Cd)});
    CHECK(max_abs(K - Kd) < 1e-13 * scale);
    CHECK(max_abs(C - Cd) < 1e-13 * scale);
    CHECK(max_abs(M - Mm) < 1e-12 * std::max(1.0, max_abs(Mm)));
    CHECK(M == M.transpose());
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
  const int n = system.num_coordinates();  // the independent ones of closed loops
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
    dq.col(j) = richardson_relative(qdd_of(&State::q), s.q(j), 1.0);
    dqd.col(j) = richardson_relative(qdd_of(&State::qd), s.qd(j), 1.0);
  }
  const double scale = std::max({1.0, max_abs(dq), max_abs(dqd)});
  CHECK(max_abs(d.dqdd_dq - dq) < 1e-6 * scale);
  CHECK(max_abs(d.dqdd_dqd - dqd) < 1e-6 * scale);
  // dqdd/dtau = M⁻¹: M·M⁻¹ = I.
  Matrix M;
  system.mass_matrix(s, M);
  CHECK(max_abs(M * d.dqdd_dtau - Matrix::Identity(n, n)) < 1e-9 * std::max(1.0, max_abs(M)));
}

// The largest |a_i - b_i| over n entries, or infinity where b_i is exactly zero and a_i is
// not: a sparse output's structural zero that a kept buffer no longer holds.
double kept_gap(const double* a, const double* b, std::size_t n) {
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (b[i] == 0.0 && a[i] != 0.0) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  return worst;
}

TEMPLATE_LIST_TEST_CASE(
    "buffers kept over many evaluations give what fresh ones give, structural zeros still zero",
    "[models][derivatives]", symdyn_test::all_models) {
  // The emitted partial velocities and kinematics derivatives are written sparsely
  // (docs/emitted_interface.md): their structural zeros are those the buffers were made with.
  const Model model = Model::from<TestType>();
  INFO("model " << model.name() << " variant " << model.variant());
  std::mt19937 rng(11);
  const int nq = model.nq(), nb = model.nbody();
  const auto partials = static_cast<std::size_t>(3 * nb * nq);
  // The model's entry points into kept buffers, at every level.
  Kinematics k = model.make_kinematics();
  RelativeMotion rel = model.make_relative_motion();
  KinematicsDerivatives dk = model.make_kinematics_derivatives();
  Matrix M = Matrix::Zero(nq, nq);
  Vector h = Vector::Zero(nq);
  const auto evaluate = [&](Kinematics& into, RelativeMotion& r, KinematicsDerivatives& d,
                            const State& s, KinematicsLevel level) {
    if (model.has_equations_of_motion())
      model.dynamics(s.t, s.q.data(), s.qd.data(), level, M.data(), h.data(), into);
    model.partial_velocities(s.t, s.q.data(), into);
    if (model.has_relative_partial_velocities())
      model.relative_partial_velocities(s.t, s.q.data(), r);
    if (model.has_kinematics_derivatives())
      model.kinematics_derivatives(s.t, s.q.data(), s.qd.data(), d);
  };
  // At states of all nq coordinates (a system's states hold the independent ones alone).
  const auto model_state = [&] {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    State s = model.initial_state();
    for (int j = 0; j < nq; ++j) s.q(j) += 0.1 * u(rng), s.qd(j) = u(rng);
    return s;
  };
  // And a system's, with force elements that read them.
  MultibodySystem worn(model);
  add_force_elements(worn);
  const bool jacobians = worn.exact_jacobians();
  Vector qdd, yd;
  Matrix Mj, C, K;
  for (int trial = 0; trial < 30; ++trial) {
    const State x = model_state();
    for (KinematicsLevel level :
         {KinematicsLevel::none, KinematicsLevel::positions, KinematicsLevel::velocities})
      evaluate(k, rel, dk, x, level);
    const State s = random_state(worn, rng);
    worn.accelerations(s, qdd, yd);
    if (jacobians) worn.jacobians(s, qdd, Mj, C, K);
  }
  const State x = model_state();
  evaluate(k, rel, dk, x, KinematicsLevel::velocities);
  Kinematics fresh_k = model.make_kinematics();
  RelativeMotion fresh_rel = model.make_relative_motion();
  KinematicsDerivatives fresh_dk = model.make_kinematics_derivatives();
  evaluate(fresh_k, fresh_rel, fresh_dk, x, KinematicsLevel::velocities);
  CHECK(kept_gap(k.dv_dqd_data(), fresh_k.dv_dqd_data(), partials) == 0.0);
  CHECK(kept_gap(k.dw_dqd_data(), fresh_k.dw_dqd_data(), partials) == 0.0);
  CHECK(kept_gap(rel.relative().dv_dqd_data(), fresh_rel.relative().dv_dqd_data(), partials) ==
        0.0);
  CHECK(kept_gap(rel.relative().dw_dqd_data(), fresh_rel.relative().dw_dqd_data(), partials) ==
        0.0);
  if (model.has_kinematics_derivatives()) {
    CHECK(kept_gap(dk.dv_dq_data(), fresh_dk.dv_dq_data(), partials) == 0.0);
    CHECK(kept_gap(dk.dw_dq_data(), fresh_dk.dw_dq_data(), partials) == 0.0);
    CHECK(kept_gap(dk.ddv_dq_data(), fresh_dk.ddv_dq_data(), partials * nq) == 0.0);
    CHECK(kept_gap(dk.ddw_dq_data(), fresh_dk.ddw_dq_data(), partials * nq) == 0.0);
  }
  // The system's kinematics and Jacobians likewise, without closed loops: their dependent
  // parameters are solved from the last solution, and the Stewart platform's may then reach
  // another assembly than a fresh system's.
  if (model.has_loops()) return;
  const State s = random_state(worn, rng);
  MultibodySystem fresh(model);
  add_force_elements(fresh);
  Kinematics worn_k = worn.evaluate_kinematics(s);
  Kinematics fresh_system_k = fresh.evaluate_kinematics(s);
  CHECK(kept_gap(worn_k.dv_dqd_data(), fresh_system_k.dv_dqd_data(), partials) == 0.0);
  CHECK(kept_gap(worn_k.dw_dqd_data(), fresh_system_k.dw_dqd_data(), partials) == 0.0);
  if (jacobians) {
    Matrix Mf, Cf, Kf;
    worn.accelerations(s, qdd, yd);
    worn.jacobians(s, qdd, Mj, C, K);
    fresh.jacobians(s, qdd, Mf, Cf, Kf);
    CHECK(K == Kf);
    CHECK(C == Cf);
  }
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
  // Dampers c0, c1 on the two joints (relative angles theta1, theta2): C = diag(c0, c1)
  // in these coordinates; with M and K in closed form (relative angles from
  // the horizontal, hanging at theta1 = -π/2), det(λ²M + λC + K) is a quartic in λ
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
  // Laws given with their derivatives are exact, those without named.
  const auto law = [](double, double q, double, const State&) { return -q * q * q; };
  system.add<CoordinateForce>(
      "cubic", 0, law,
      [](double, double q, double, const State&, Vector& dq, Vector&) { dq(0) = -3.0 * q * q; });
  system.add<CoordinateTracking>(
      "servo", 1, 5.0, 0.5, [](double t) { return t; }, [](double) { return 1.0; });
  const auto push = [](const State&, const Kinematics&, Loads& loads) {
    loads.add_generalized(1, 1.0);
  };
  system.add<UserForce>(
      "push", push, KinematicsLevel::none,
      [](const State&, const Kinematics&, const KinematicsDerivatives&, Matrix&, Matrix&) {});
  system.add<PointLoad>(
      "gust", BodyPoint{1, Vec3::Zero()},
      [](const State&, const Kinematics&, Vec3& f, Vec3&) { f = Vec3(0.0, 1.0, 0.0); },
      [](const State&, const Kinematics&, const KinematicsDerivatives&, Vec3& f, Vec3&, Matrix&,
         Matrix&) { f = Vec3(0.0, 1.0, 0.0); });
  CHECK(system.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for load 'wind'");
  system.add<CoordinateForce>("soft", 1, law);
  system.add<UserForce>("shove", push, KinematicsLevel::none);
  CHECK(system.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for load 'wind', coordinate "
        "force 'soft', user force 'shove'");
  system.set_exact_load_derivatives(false);
  CHECK(system.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for coordinate spring 'hip', "
        "spring 'strut', load 'wind', coordinate force 'cubic', coordinate tracking 'servo', user "
        "force 'push', load 'gust', coordinate force 'soft', user force 'shove'");
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
  A.col(0) = richardson_relative(of_q, s.q(0), 1.0);
  A.col(1) = richardson_relative(of_qd, s.qd(0), 1.0);
  B.col(0) = richardson_relative(of_u, u(0), 1.0);
  INFO("A\n" << d.A << "\ndifferences\n" << A << "\nB\n" << d.B << "\ndifferences\n" << B);
  CHECK(max_abs(d.A - A) < 1e-9 * std::max(1.0, max_abs(A)));
  CHECK(max_abs(d.B - B) < 1e-9 * std::max(1.0, max_abs(B)));
}

TEST_CASE("a bushing's exact load derivatives equal Richardson differences",
          "[models][derivatives][elements]") {
  BushingProperties p;
  p.stiffness = Vec3(300.0, 200.0, 500.0);
  p.damping = Vec3(3.0, 2.0, 4.0);
  p.rotational_stiffness = Vec3(40.0, 60.0, 30.0);
  p.rotational_damping = Vec3(0.5, 0.3, 0.8);
  p.preload_force = Vec3(5.0, -3.0, 2.0);
  p.preload_torque = Vec3(0.4, -0.2, 0.1);
  const Mat3 axes = Eigen::AngleAxisd(0.4, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  std::mt19937 rng(11);
  for (const char* order : {"xyz", "zyx", "yxz"}) {
    for (const int a : {ground, 0}) {
      Rig rig(rng);
      rig.with.add<Bushing>("mount", BodyFrame{a, Vec3(0.1, 0.05, 0.2), axes},
                            BodyFrame{gripper, Vec3(-0.05, 0.02, 0.1), axes.transpose()}, p, order);
      INFO("order " << order << ", frame A on body " << a);
      check_load_derivatives(rig.with, rig.bare, rig.s);
    }
  }
}

namespace {

// A random state of the rig and the plane of normal ±tilted_normal at penetration pen of
// the contact point of make(plane)'s element, the sign that makes the contact point's
// velocity separate from the plane (vP·n > 0) or approach it, as asked (neither depends
// on the plane's point).
template <class Make>
Plane place(Rig& rig, std::mt19937& rng, double pen, bool separating, Make make) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    rig.s = random_state(rig.bare, rng);
    const Kinematics& k = rig.kinematics();
    for (const double sign : {1.0, -1.0}) {
      const Vec3 n = sign * tilted_normal;
      const Vec3 P = make(Plane{Vec3::Zero(), n})->evaluate(k).contact_point;
      if ((k.velocity_at(gripper, P).dot(n) > 0.0) == separating) return plane_at(P, n, pen);
    }
  }
  FAIL("no state with the contact point " << (separating ? "separating" : "approaching"));
  return {};
}

}  // namespace

TEST_CASE("a plane contact's exact load derivatives equal Richardson differences in each regime",
          "[models][derivatives][elements]") {
  ContactProperties base;
  base.stiffness = 1e5;
  base.stiffness_exponent = 1.5;
  base.damping = 2e3;
  base.damping_exponent = 1.0;
  base.friction = 0.6;
  base.slip_speed = 1e-3;
  const Vec3 centre(0.1, 0.02, -0.05);
  const double radius = 0.05;
  std::mt19937 rng(5);
  const auto make = [&](const Plane& plane, const ContactProperties& p) {
    return std::make_shared<PlaneContact>("ball", gripper, centre, radius, plane, p);
  };
  // A contact whose properties tune(p, vC, n) sets from the contact point's velocity.
  const auto run = [&](const char* regime, double pen, bool separating, double step, auto tune) {
    INFO("regime: " << regime);
    Rig rig(rng);
    const Plane plane =
        place(rig, rng, pen, separating, [&](const Plane& at) { return make(at, base); });
    const Kinematics& k = rig.kinematics();
    const Vec3 C = make(plane, base)->evaluate(k).contact_point;
    ContactProperties p = base;
    tune(p, Vec3(k.velocity_at(gripper, C)), plane.normal);
    const auto contact = make(plane, p);
    rig.with.add(contact);
    const PlaneContact::Result r = contact->evaluate(rig.kinematics());
    CHECK(std::abs(r.penetration - pen) < 1e-12);
    check_load_derivatives(rig.with, rig.bare, rig.s, step);
    return r;
  };
  const auto keep = [](ContactProperties&, const Vec3&, const Vec3&) {};
  // The damping that makes N = 0: Kn pen^pk = Cd pen^pd (vC·n) for a separating point.
  const auto damping_factor = [&](double factor, double pen) {
    return [=](ContactProperties& p, const Vec3& vC, const Vec3& n) {
      p.damping = factor * p.stiffness * std::pow(pen, p.stiffness_exponent) /
                  (std::pow(pen, p.damping_exponent) * vC.dot(n));
    };
  };
  const auto slip_speed_factor = [&](double factor, FrictionRegularization reg) {
    return [=](ContactProperties& p, const Vec3& vC, const Vec3& n) {
      p.slip_speed = factor * (vC - vC.dot(n) * n).norm();
      p.regularization = reg;
    };
  };
  using enum FrictionRegularization;
  CHECK(run("apart", -0.01, false, 1.0, keep).normal_force == 0.0);
  CHECK(run("apart, near touching", -1e-4, false, 0.01, keep).normal_force == 0.0);
  CHECK(run("touching, approaching", 0.02, false, 1.0, keep).normal_force > 0.0);
  CHECK(run("touching, separating", 0.02, true, 1.0, keep).normal_force > 0.0);
  CHECK(run("just touching", 1e-3, false, 0.1, keep).normal_force > 0.0);
  CHECK(run("pulling (N clipped to 0)", 0.02, true, 1.0, damping_factor(2.0, 0.02)).normal_force ==
        0.0);
  CHECK(run("N just above 0", 0.02, true, 0.1, damping_factor(0.9, 0.02)).normal_force > 0.0);
  CHECK(run("N just clipped", 0.02, true, 0.1, damping_factor(1.1, 0.02)).normal_force == 0.0);
  CHECK(run("linear friction below v_s", 0.02, false, 1.0, slip_speed_factor(3.0, linear))
            .normal_force > 0.0);
  CHECK(run("linear friction just below v_s", 0.02, false, 0.1, slip_speed_factor(1.05, linear))
            .normal_force > 0.0);
  CHECK(run("linear friction just above v_s", 0.02, false, 0.1, slip_speed_factor(0.95, linear))
            .normal_force > 0.0);
  CHECK(run("smooth friction", 0.02, false, 1.0, slip_speed_factor(0.5, smooth)).normal_force >
        0.0);
}

TEST_CASE("a simple tyre's exact load derivatives equal Richardson differences in each regime",
          "[models][derivatives][elements]") {
  SimpleTyreProperties base;  // the trike's: R 0.3, k 2e5, c 500, mu 0.9, eps 0.05
  base.centre = Vec3(0.05, 0.0, 0.0);
  base.axis = Vec3(0.1, 1.0, 0.2).normalized();
  std::mt19937 rng(6);
  const auto make = [&](const Plane& plane, const SimpleTyreProperties& p) {
    return std::make_shared<SimpleTyre>("wheel", gripper, p, plane);
  };
  // damping_factor > 0: the damping times that which makes N = k pen - c vP·n = 0.
  const auto run = [&](const char* regime, double pen, bool separating, double step,
                       double damping_factor = 0.0) {
    INFO("regime: " << regime);
    Rig rig(rng);
    const Plane plane =
        place(rig, rng, pen, separating, [&](const Plane& at) { return make(at, base); });
    SimpleTyreProperties p = base;
    if (damping_factor > 0.0) {
      const Vec3 vP = make(plane, base)->evaluate(rig.kinematics()).contact_velocity;
      p.damping = damping_factor * p.stiffness * pen / vP.dot(plane.normal);
    }
    const auto tyre = make(plane, p);
    rig.with.add(tyre);
    const SimpleTyre::Result r = tyre->evaluate(rig.kinematics());
    CHECK(std::abs(r.penetration - pen) < 1e-12);
    check_load_derivatives(rig.with, rig.bare, rig.s, step);
    return r;
  };
  CHECK(run("off the ground", -0.01, false, 1.0).normal_force == 0.0);
  CHECK(run("just off the ground", -1e-4, false, 0.01).normal_force == 0.0);
  CHECK(run("on the ground, approaching", 0.01, false, 1.0).normal_force > 0.0);
  CHECK(run("on the ground, separating", 0.01, true, 1.0).normal_force > 0.0);
  CHECK(run("just touching", 1e-3, false, 0.1).normal_force > 0.0);
  CHECK(run("pulling (N clipped to 0)", 0.01, true, 1.0, 2.0).normal_force == 0.0);
  CHECK(run("N just above 0", 0.01, true, 0.1, 0.9).normal_force > 0.0);
  CHECK(run("N just clipped", 0.01, true, 0.1, 1.1).normal_force == 0.0);
}

TEST_CASE("a Gim tyre's exact load derivatives equal Richardson differences in each regime",
          "[models][derivatives][elements]") {
  GimTyreProperties base;  // r1 0.3, r2 0.1, Kz 2e5, Cz 500, Fznom 3000, mu 1 / 0.8
  base.centre = Vec3(0.05, 0.0, 0.0);
  base.axis = Vec3(0.1, 1.0, 0.2).normalized();
  std::mt19937 rng(8);
  const auto make = [&](const Plane& plane, const GimTyreProperties& p) {
    return std::make_shared<GimTyre>("wheel", gripper, p, plane);
  };
  // A tyre whose properties (and the rig's speeds) tune(p, rig, plane) sets.
  const auto run = [&](const char* regime, double pen, bool separating, double step, auto tune) {
    INFO("regime: " << regime);
    Rig rig(rng);
    const Plane plane =
        place(rig, rng, pen, separating, [&](const Plane& at) { return make(at, base); });
    GimTyreProperties p = base;
    tune(p, rig, plane);
    const auto tyre = make(plane, p);
    rig.with.add(tyre);
    const GimTyre::Result r = tyre->evaluate(rig.kinematics());
    CHECK(std::abs(r.penetration - pen) < 1e-12);
    check_load_derivatives(rig.with, rig.bare, rig.s, step);
    return r;
  };
  const auto keep = [](GimTyreProperties&, Rig&, const Plane&) {};
  // The vertical damping times that which makes Fz = Kz pen - sqrt(Kz pen / Fznom) Cz vP·n = 0.
  const auto damping_factor = [&](double factor) {
    return [=, &make](GimTyreProperties& p, Rig& rig, const Plane& plane) {
      const GimTyre::Result r = make(plane, p)->evaluate(rig.kinematics());
      const double elastic = p.Kz * r.penetration;
      const Vec3 vP = rig.kinematics().velocity_at(gripper, r.contact_point);
      p.Cz = factor * elastic / (std::sqrt(elastic / p.Fznom) * vP.dot(plane.normal));
    };
  };
  // The slip stiffnesses scaled to make |(X, Y + 3 G)| / (3 mu Fz) = ratio: full sliding
  // from 1 on (every stiffness is proportional to its nominal value).
  const auto sliding_ratio = [&](double ratio) {
    return [=, &make](GimTyreProperties& p, Rig& rig, const Plane& plane) {
      const GimTyre::Result r = make(plane, p)->evaluate(rig.kinematics());
      const double load = r.Fz / p.Fznom;
      const double X = p.Clongnom * load * r.slip_long, Y = p.Clatnom * load * r.slip_lat;
      const double G = p.Ccambernom * load * r.camber;
      const double factor = ratio * 3.0 * r.friction * r.Fz / std::hypot(X, Y + 3.0 * G);
      p.Clongnom *= factor;
      p.Clatnom *= factor;
      p.Ccambernom *= factor;
    };
  };
  // The speeds scaled to make the centre's forward speed |vC·x| = speed (V = max(it, 1e-3)).
  const auto forward_speed = [&](double speed) {
    return [=, &make](GimTyreProperties& p, Rig& rig, const Plane& plane) {
      const Kinematics& k = rig.kinematics();
      const GimTyre::Result r = make(plane, p)->evaluate(k);
      const Vec3 C = k.point_position(gripper, p.centre);
      rig.scale_speeds(speed / std::abs(k.velocity_at(gripper, C).dot(r.x)));
    };
  };
  CHECK(run("off the ground", -0.01, false, 1.0, keep).Fz == 0.0);
  CHECK(run("just off the ground", -1e-4, false, 0.01, keep).Fz == 0.0);
  CHECK(run("just touching", 1e-3, false, 0.1, keep).Fz > 0.0);
  CHECK(run("pulling (Fz clipped to 0)", 0.01, true, 1.0, damping_factor(2.0)).Fz == 0.0);
  CHECK(run("Fz just above 0", 0.01, true, 0.1, damping_factor(0.9)).Fz > 0.0);
  CHECK(run("Fz just clipped", 0.01, true, 0.1, damping_factor(1.1)).Fz == 0.0);
  for (const double ratio : {0.3, 0.97}) {
    const GimTyre::Result r =
        run("adhesion", 0.01, false, ratio < 0.9 ? 1.0 : 0.1, sliding_ratio(ratio));
    CHECK_FALSE(r.brush.sliding);
    CHECK(r.brush.adhesion > 0.0);
    CHECK(r.brush.adhesion < 1.0);
  }
  CHECK(run("full sliding, just", 0.01, false, 0.1, sliding_ratio(1.03)).brush.sliding);
  CHECK(run("at the forward speed's floor", 0.01, false, 0.01, forward_speed(5e-4)).Fz > 0.0);
  CHECK(run("just below the floor", 0.01, false, 0.01, forward_speed(0.95e-3)).Fz > 0.0);
  CHECK(run("just above the floor", 0.01, false, 0.01, forward_speed(1.05e-3)).Fz > 0.0);
  // Random states at nominal properties: full sliding, mu on both sides of the slip of 1.
  int slip_below_1 = 0, slip_above_1 = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const GimTyre::Result r = run("nominal", 0.01, false, 1.0, keep);
    CHECK(r.Fz > 0.0);
    const double slip = std::hypot(r.slip_long, r.slip_lat);
    slip_below_1 += slip < 0.99;
    slip_above_1 += slip > 1.01;
  }
  CHECK(slip_below_1 > 0);
  CHECK(slip_above_1 > 0);
}

namespace {

// A coordinate force on robot3d's arm extension that also reads the arm's pitch
// through the state, Q = -k·e³ - c·qd·|qd| + a·sin(q_pitch)·qd with e = q - 0.5,
// and its derivatives (rows of dQ/dq and dQ/dqd).
constexpr int pitch = 1, extension = 2;

double extension_law(double, double q, double qd, const State& s) {
  const double e = q - 0.5;
  return -400.0 * e * e * e - 3.0 * qd * std::abs(qd) + 20.0 * std::sin(s.q(pitch)) * qd;
}

void extension_derivatives(double, double q, double qd, const State& s, Vector& dQ_dq,
                           Vector& dQ_dqd) {
  const double e = q - 0.5;
  dQ_dq(extension) = -1200.0 * e * e;
  dQ_dq(pitch) = 20.0 * std::cos(s.q(pitch)) * qd;
  dQ_dqd(extension) = -6.0 * std::abs(qd) + 20.0 * std::sin(s.q(pitch));
}

// Quadratic drag F = -c·|v_P|·v_P at a point P of the gripper (a user force reading
// the velocities) and its Jacobian: with J_j = ∂P/∂q_j and
// ∂F/∂v_P = -c·(|v_P|·I + v_P·v_Pᵀ/|v_P|) (|v_P| > 0), Q_j = F·J_j gives
// ∂Q_j/∂q_k = ∂F/∂v_P·∂v_P/∂q_k·J_j + F·∂J_j/∂q_k and ∂Q_j/∂qd_k = ∂F/∂v_P·J_k·J_j.
// (∂F/∂v_P tends to 0 with v_P.)
const Vec3 nozzle(0.05, 0.0, 0.1);
constexpr double drag_coefficient = 0.8;

void add_drag(const State&, const Kinematics& k, Loads& loads) {
  const Vec3 v = k.point_velocity(gripper, nozzle);
  loads.add_force_at(gripper, k, k.point_position(gripper, nozzle),
                     -drag_coefficient * v.norm() * v);
}

// `complete` false leaves out F·∂J_j/∂q_k: a wrong Jacobian.
UserForce::Jacobian drag_jacobian(bool complete = true) {
  return [complete](const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                    Matrix& dQ_dq, Matrix& dQ_dqd) {
    const Vec3 v = k.point_velocity(gripper, nozzle), r = k.to_global(gripper, nozzle);
    const Vec3 F = -drag_coefficient * v.norm() * v;
    const Mat3 dF_dv =
        v.norm() > 0.0
            ? Mat3(-drag_coefficient * (v.norm() * Mat3::Identity() + v * v.transpose() / v.norm()))
            : Mat3::Zero();
    const auto n = static_cast<int>(s.q.size());
    for (int kk = 0; kk < n; ++kk) {
      const Vec3 dF_dq = dF_dv * dk.point_velocity_derivative(k, gripper, r, kk);
      const Vec3 dF_dqd = dF_dv * dk.point_partial(k, gripper, r, kk);
      for (int j = 0; j < n; ++j) {
        const Vec3 J = dk.point_partial(k, gripper, r, j);
        dQ_dq(j, kk) = dF_dq.dot(J);
        if (complete) dQ_dq(j, kk) += F.dot(dk.point_partial_derivative(k, gripper, r, j, kk));
        dQ_dqd(j, kk) = dF_dqd.dot(J);
      }
    }
  };
}

// A generalized drag on the turret, Q_0 = -0.3·qd_0·|qd_0| (reads nothing), and its Jacobian.
void add_turret_drag(const State& s, const Kinematics&, Loads& loads) {
  loads.add_generalized(0, -0.3 * s.qd(0) * std::abs(s.qd(0)));
}

void turret_drag_jacobian(const State& s, const Kinematics&, const KinematicsDerivatives&, Matrix&,
                          Matrix& dQ_dqd) {
  dQ_dqd(0, 0) = -0.6 * std::abs(s.qd(0));
}

}  // namespace

TEST_CASE("coordinate forces' and user forces' derivative laws equal Richardson differences",
          "[models][derivatives][elements]") {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 4; ++trial) {
    Rig rig(rng);
    rig.with.add<CoordinateForce>("extension", extension, extension_law, extension_derivatives);
    rig.with.add<UserForce>("drag", add_drag, KinematicsLevel::velocities, drag_jacobian());
    rig.with.add<UserForce>("turret drag", add_turret_drag, KinematicsLevel::none,
                            turret_drag_jacobian);
    INFO("trial " << trial);
    check_load_derivatives(rig.with, rig.bare, rig.s);
    // The laws' part is not zero: the check compares something.
    const LoadDerivativeErrors e = load_derivative_errors(rig.with, rig.bare, rig.s);
    CHECK(e.scale > 10.0);
  }
}

TEST_CASE("a wrong derivative law differs from Richardson differences",
          "[models][derivatives][elements]") {
  std::mt19937 rng(29);
  SECTION("a coordinate force's, without its dependence on another coordinate") {
    Rig rig(rng);
    rig.with.add<CoordinateForce>(
        "extension", extension, extension_law,
        [](double t, double q, double qd, const State& s, Vector& dQ_dq, Vector& dQ_dqd) {
          extension_derivatives(t, q, qd, s, dQ_dq, dQ_dqd);
          dQ_dq(pitch) = 0.0;
        });
    REQUIRE(rig.with.jacobian_method() == "exact (emitted derivatives)");
    const LoadDerivativeErrors e = load_derivative_errors(rig.with, rig.bare, rig.s);
    CHECK(e.dq > 1e-3 * e.scale);
    CHECK(e.dqd < 1e-7 * e.scale);
  }
  SECTION("a user force's, without the derivative of its point's partial velocities") {
    Rig rig(rng);
    rig.scale_speeds(3.0);
    rig.with.add<UserForce>("drag", add_drag, KinematicsLevel::velocities, drag_jacobian(false));
    REQUIRE(rig.with.jacobian_method() == "exact (emitted derivatives)");
    const LoadDerivativeErrors e = load_derivative_errors(rig.with, rig.bare, rig.s);
    CHECK(e.dq > 1e-3 * e.scale);
    CHECK(e.dqd < 1e-7 * e.scale);
  }
}

TEST_CASE("derivative laws that resize or give no finite value are refused, naming the element",
          "[models][derivatives][elements]") {
  MultibodySystem system(Model::from<symdyn_generated::robot3d_absolute>());
  std::mt19937 rng(31);
  const State s = random_state(system, rng);
  const Vector qdd = Vector::Zero(system.num_coordinates());
  Matrix M, C, K;
  SECTION("a coordinate force's not finite") {
    system.add<CoordinateForce>("bad", extension, extension_law,
                                [](double, double, double, const State&, Vector& dQ_dq, Vector&) {
                                  dQ_dq(0) = std::numeric_limits<double>::quiet_NaN();
                                });
    CHECK_THROWS_AS(system.jacobians(s, qdd, M, C, K), NumericError);
    CHECK_THROWS_WITH(system.jacobians(s, qdd, M, C, K),
                      Catch::Contains("coordinate force 'bad': its law's derivatives with "
                                      "respect to q are not finite"));
  }
  SECTION("a user force's resized") {
    system.add<UserForce>("bad", add_turret_drag, KinematicsLevel::none,
                          [](const State&, const Kinematics&, const KinematicsDerivatives&, Matrix&,
                             Matrix& dQ_dqd) { dQ_dqd.resize(1, 1); });
    CHECK_THROWS_AS(system.jacobians(s, qdd, M, C, K), ModelError);
    CHECK_THROWS_WITH(system.jacobians(s, qdd, M, C, K),
                      Catch::Contains("user force 'bad': its law's derivatives with respect to qd "
                                      "were resized to 1 x 1; expected 5 x 5"));
  }
}

TEST_CASE("Newmark with the laws' derivatives follows the differenced run, evaluating them less",
          "[models][derivatives][elements]") {
  struct Run {
    State end;
    Statistics stats;
    long law_calls = 0;
  };
  const State start = [] {
    MultibodySystem system(Model::from<symdyn_generated::robot3d_absolute>());
    State s = system.initial_state();
    s.q(extension) = 0.7;
    s.qd << 1.0, -0.5, 0.3, 2.0, -1.0;
    return s;
  }();
  const auto run = [&](const char* integrator, double tolerance, bool with_derivatives) {
    MultibodySystem system(Model::from<symdyn_generated::robot3d_absolute>());
    auto calls = std::make_shared<long>(0);
    system.add<CoordinateForce>(
        "extension", extension,
        [calls](double t, double q, double qd, const State& s) {
          ++*calls;
          return extension_law(t, q, qd, s);
        },
        with_derivatives ? extension_derivatives : CoordinateForce::LawDerivatives());
    system.add<UserForce>(
        "drag",
        [calls](const State& s, const Kinematics& k, Loads& loads) {
          ++*calls;
          add_drag(s, k, loads);
        },
        KinematicsLevel::velocities, with_derivatives ? drag_jacobian() : nullptr);
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = tolerance;
    auto i = make_integrator(integrator, o);
    const State end = i->integrate(system, start, 1.0);
    return Run{end, i->statistics(), *calls};
  };
  const Run reference = run("dop853", 1e-12, false);
  const Run exact = run("newmark", 1e-6, true), differenced = run("newmark", 1e-6, false);
  const auto distance = [](const State& a, const State& b) {
    return std::max(max_abs(a.q - b.q), max_abs(a.qd - b.qd));
  };
  INFO("exact: error " << distance(exact.end, reference.end) << ", " << exact.stats.steps
                       << " steps, " << exact.stats.newton_iterations << " Newton iterations, "
                       << exact.stats.residual_evaluations << " residuals, " << exact.law_calls
                       << " law calls; differenced: error "
                       << distance(differenced.end, reference.end) << ", "
                       << differenced.stats.steps << " steps, "
                       << differenced.stats.newton_iterations << " Newton iterations, "
                       << differenced.stats.residual_evaluations << " residuals, "
                       << differenced.law_calls << " law calls");
  CHECK(distance(exact.end, differenced.end) < 1e-6);
  CHECK(distance(exact.end, reference.end) < 1e-4);
  CHECK(exact.law_calls < differenced.law_calls);
  CHECK(exact.stats.newton_iterations <= differenced.stats.newton_iterations);
  CHECK(exact.stats.residual_evaluations <= differenced.stats.residual_evaluations);
}
