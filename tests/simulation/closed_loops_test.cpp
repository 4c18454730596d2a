// Closed kinematic loops solved at run time (runtime/loop_closure.hpp): the
// slider-crank with its loop given implicitly against the same mechanism in
// closed form, the four-bar against the two-circle intersection, the loops'
// emitted Jacobians and bias against differences, drift and energy over a
// long run, and the errors of a loop that does not close.

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "differences.hpp"
#include "four_bar.hpp"
#include "four_bar_parametric.hpp"
#include "random_state.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_implicit.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;
namespace gen = symdyn_generated;
using symdyn::testing::max_abs;
using symdyn::testing::one_coordinate_state;
constexpr double pi = std::numbers::pi;

// |a - b| relative to the larger of them (and 1).
double relative(const Matrix& a, const Matrix& b) {
  return max_abs(a - b) / std::max({1.0, max_abs(a), max_abs(b)});
}

// An angle in (-pi, pi].
double wrapped(double a) {
  return std::remainder(a, 2 * pi);
}

// The loops' equations g at x (ncon), and their Jacobians (ncon x n, ncon x ncon).
struct Loops {
  Vector g, g_t;
  Matrix g_q, g_p;
};
Loops constraints(const Model& model, double t, const Vector& x) {
  const int n = model.nindependent(), m = model.ncon();
  Loops l{Vector(m), Vector(m), Matrix(n, m), Matrix(m, m)};
  model.constraints(t, x.data(), l.g.data(), l.g_q.data(), l.g_p.data(), l.g_t.data());
  l.g_q.transposeInPlace();  // row-major arrays
  l.g_p.transposeInPlace();
  return l;
}

// The four-bar's joint C by the two-circle intersection (circles about A, radius
// r2, and about D, radius r3), on the side of A->D where the model is assembled
// (its left), and the angles phi (coupler relative to crank) and psi (rocker).
struct FourBarPose {
  double phi, psi;
};
FourBarPose four_bar_closed_form(double q0) {
  const double r1 = 0.1, r2 = 0.35, r3 = 0.3, d = 0.4;
  const Eigen::Vector2d A(r1 * std::cos(q0), r1 * std::sin(q0)), D(d, 0.0);
  const double e = (D - A).norm();
  const double a = (r2 * r2 - r3 * r3 + e * e) / (2 * e), h = std::sqrt(r2 * r2 - a * a);
  const Eigen::Vector2d u = (D - A) / e, left(-u.y(), u.x());
  const Eigen::Vector2d C = A + a * u + h * left;
  return {std::atan2(C.y() - A.y(), C.x() - A.x()) - q0, std::atan2(C.y() - D.y(), C.x() - D.x())};
}

}  // namespace

TEST_CASE("the implicit slider-crank equals the explicit one at random states", "[models][loops]") {
  MultibodySystem explicit_(Model::from<gen::slider_crank_dependent>());
  MultibodySystem implicit(Model::from<gen::slider_crank_implicit>());
  REQUIRE(implicit.model().has_loops());
  REQUIRE(implicit.num_coordinates() == 1);
  REQUIRE(implicit.model().nq() == 3);
  CHECK(implicit.model().loop_names() == std::vector<std::string>{"crank_pin"});
  std::mt19937 rng(20261126u);
  std::uniform_real_distribution<double> angle(-pi, pi), rate(-50.0, 50.0), time(0.0, 1.0);
  Matrix Me, Mi;
  Vector he, hi, qdde, qddi, yd;
  Kinematics dep = explicit_.model().make_kinematics();
  for (int k = 0; k < 200; ++k) {
    const State s = one_coordinate_state(time(rng), angle(rng), rate(rng));
    CAPTURE(k, s.t, s.q(0), s.qd(0));
    // States far apart: each assembled from the model's guesses, as the closed
    // form's branch (|alpha| < pi/2), not from the last state's solution.
    implicit.reset_loops();
    explicit_.mass_matrix(s, Me);
    implicit.mass_matrix(s, Mi);
    CHECK(relative(Me, Mi) <= 1e-12);
    explicit_.bias_forces_emitted(s, he);
    implicit.bias_forces_emitted(s, hi);
    CHECK(relative(he, hi) <= 1e-12);
    explicit_.accelerations(s, qdde, yd);
    implicit.accelerations(s, qddi, yd);
    CHECK(relative(qdde, qddi) <= 1e-12);
    // The implicit parameters and their rates are alpha, x of the closed form.
    const State x = implicit.extended_state(s);
    explicit_.model().dependent_parameters(s.t, s.q.data(), s.qd.data(), qdde.data(), dep);
    for (int j = 0; j < 2; ++j) {
      CHECK(std::abs(x.q(1 + j) - dep.p()[static_cast<std::size_t>(j)]) <=
            1e-12 * (1 + std::abs(dep.p()[static_cast<std::size_t>(j)])));
      CHECK(std::abs(x.qd(1 + j) - dep.pd()[static_cast<std::size_t>(j)]) <=
            1e-12 * (1 + std::abs(dep.pd()[static_cast<std::size_t>(j)])));
    }
    // Positions and velocities of every body.
    const Kinematics ke = explicit_.evaluate_kinematics(s);
    const Kinematics& ki = implicit.evaluate_kinematics(s);
    for (int i = 0; i < 3; ++i) {
      CHECK(relative(ke.R(i), ki.R(i)) <= 1e-12);
      CHECK(relative(ke.x(i), ki.x(i)) <= 1e-12);
      CHECK(relative(ke.v(i), ki.v(i)) <= 1e-12);
    }
  }
}

TEST_CASE(
    "the four-bar's position analysis is the two-circle intersection, its rates the "
    "derivative",
    "[models][loops]") {
  MultibodySystem system(Model::from<gen::four_bar>());
  REQUIRE(system.num_coordinates() == 1);
  // Around the crank's whole turn, each solve starting from the last one.
  for (int k = 0; k <= 360; ++k) {
    const double q0 = 2 * pi * k / 360, qd0 = 3.0;
    CAPTURE(q0);
    const State x = system.extended_state(one_coordinate_state(0.0, q0, qd0));
    const FourBarPose expected = four_bar_closed_form(q0);
    CHECK(std::abs(wrapped(x.q(1) - expected.phi)) <= 1e-12);
    CHECK(std::abs(wrapped(x.q(2) - expected.psi)) <= 1e-12);
    // pd = dp/dq0·qd0 by central differences of the closed form.
    const double h = 1e-5;
    const FourBarPose plus = four_bar_closed_form(q0 + h), minus = four_bar_closed_form(q0 - h);
    CHECK(std::abs(x.qd(1) - wrapped(plus.phi - minus.phi) / (2 * h) * qd0) <= 1e-7);
    CHECK(std::abs(x.qd(2) - wrapped(plus.psi - minus.psi) / (2 * h) * qd0) <= 1e-7);
  }
}

TEST_CASE("the emitted loop Jacobians and bias agree with differences of g", "[models][loops]") {
  MultibodySystem system(Model::from<gen::four_bar>());
  const Model& model = system.model();
  std::mt19937 rng(7u);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    // Any x (the equations need not hold for their derivatives).
    Vector x(3), xd(3);
    for (int j = 0; j < 3; ++j) x(j) = 2 * u(rng), xd(j) = 3 * u(rng);
    CAPTURE(x.transpose(), xd.transpose());
    const Loops at = constraints(model, 0.0, x);
    const double h = 1e-6;
    Matrix g_x(2, 3);
    for (int j = 0; j < 3; ++j) {
      Vector plus = x, minus = x;
      plus(j) += h;
      minus(j) -= h;
      g_x.col(j) = (constraints(model, 0.0, plus).g - constraints(model, 0.0, minus).g) / (2 * h);
    }
    CHECK(max_abs(g_x.leftCols(1) - at.g_q) <= 1e-8);
    CHECK(max_abs(g_x.rightCols(2) - at.g_p) <= 1e-8);
    CHECK(max_abs(at.g_t) == 0.0);  // no time in these loops
    // gamma = d/dt(g_x)·xd, g_x differenced along xd.
    const auto jacobian = [&](const Vector& y) {
      const Loops l = constraints(model, 0.0, y);
      Matrix j(2, 3);
      j << l.g_q, l.g_p;
      return j;
    };
    const Vector expected = (jacobian(x + h * xd) - jacobian(x - h * xd)) / (2 * h) * xd;
    Vector gamma(2);
    model.constraint_bias(0.0, x.data(), xd.data(), gamma.data());
    CHECK(max_abs(gamma - expected) <= 1e-7 * (1 + max_abs(expected)));
  }
}

TEST_CASE("the free four-bar keeps its loop closed and its energy over 100 s", "[models][loops]") {
  MultibodySystem system(Model::from<gen::four_bar>());
  const Model& model = system.model();
  IntegratorOptions o;
  o.relative_tolerance = 1e-11;
  o.absolute_tolerance = 1e-11;
  o.output_interval = 0.1;
  const double e0 = system.energies(system.initial_state()).total();
  double drift = 0.0, velocity_drift = 0.0, energy_drift = 0.0, kinetic = 0.0;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const State x = system.extended_state(s);
    const Loops l = constraints(model, s.t, x.q);
    drift = std::max(drift, max_abs(l.g));
    velocity_drift =
        std::max(velocity_drift, max_abs(l.g_q * x.qd.head(1) + l.g_p * x.qd.tail(2) + l.g_t));
    const Energies e = system.energies(s);
    energy_drift = std::max(energy_drift, std::abs(e.total() - e0));
    kinetic = std::max(kinetic, e.kinetic);
  };
  const State end = make_integrator("dopri5", o)->integrate(system, system.initial_state(), 100.0);
  CHECK(end.t == 100.0);
  CHECK(kinetic > 0.1);   // it turned (5 rad/s at the start and gravity)
  CHECK(drift <= 1e-10);  // m
  CHECK(velocity_drift <= 1e-10);
  CHECK(energy_drift / kinetic < 1e-7);
}

TEST_CASE("a loop at its toggle position or that cannot close is an error naming it",
          "[models][loops][errors]") {
  MultibodySystem system(Model::from<gen::four_bar_parametric>());
  Vector qdd, yd;
  SECTION("singular g_p: the coupler and rocker stretched in line") {
    // |AD| = r2 + r3 at crank = 0: C = (0.25, 0), phi = 0, psi = pi.
    system.set_parameter("r2", 0.15);
    system.set_parameter("r3", 0.15);
    system.set_loop_guess(Eigen::Vector2d(0.0, pi));
    CHECK_THROWS_WITH(system.accelerations(one_coordinate_state(0.5, 0.0, 1.0), qdd, yd),
                      Catch::Contains("t = 0.5: loop 'C' at a singular configuration") &&
                          Catch::Contains("toggle") && Catch::Contains("crank = 0, phi = 0"));
  }
  SECTION("no convergence: the coupler and rocker too short to reach") {
    // |AD| = 0.7 > r2 + r3 = 0.65 at crank = pi.
    system.set_parameter("r1", 0.3);
    CHECK_THROWS_WITH(system.accelerations(one_coordinate_state(2.0, pi, 0.0), qdd, yd),
                      Catch::Contains("t = 2: loop 'C' does not close") &&
                          Catch::Contains("did not converge") &&
                          Catch::Contains("crank = 3.14159"));
  }
  SECTION("a state in the extended coordinates is refused") {
    State x = system.model().initial_state();
    CHECK_THROWS_AS(system.accelerations(x, qdd, yd), ModelError);
    CHECK_THROWS_WITH(system.accelerations(x, qdd, yd),
                      Catch::Contains("the independent coordinates crank of its closed loops"));
  }
}

TEST_CASE("loop models without constraint_derivatives report differenced Jacobians",
          "[models][loops]") {
  MultibodySystem system(Model::from<gen::four_bar_parametric>());
  CHECK_FALSE(system.exact_jacobians());
  CHECK(system.jacobian_method() ==
        "central differences of the residual (closed loops: no exact derivatives)");
  // The residual vanishes at the accelerations, and df/dqdd is the reduced M.
  const State s = one_coordinate_state(0.3, 0.7, 2.0);
  Vector qdd, yd, f, g;
  system.accelerations(s, qdd, yd);
  system.residual(s, qdd, yd, f, g);
  Matrix M, C, K;
  system.jacobians(s, qdd, M, C, K);
  CHECK(max_abs(f) <= 1e-12 * (1 + max_abs(M)));
  // f(qdd + e) - f(qdd) = M·e (f is affine in qdd).
  Vector fe, e = Vector::Constant(1, 0.5);
  system.residual(s, qdd + e, yd, fe, g);
  CHECK(max_abs(fe - f - M * e) <= 1e-12 * (1 + max_abs(M)));
}

namespace {

// df/dq and df/dqd of the reduced residual at (s, qdd) by Richardson's differences.
void richardson_jacobians(MultibodySystem& system, const State& s, const Vector& qdd, Matrix& C,
                          Matrix& K) {
  symdyn::testing::residual_jacobians_by_differences(system, s, qdd, C, K,
                                                     [](double) { return 1e-3; });
}

template <class Generated>
void check_exact_loop_jacobians(std::uint32_t seed) {
  MultibodySystem system(Model::from<Generated>());
  REQUIRE(system.exact_jacobians());
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-1.0, 1.0), rate(-20.0, 20.0), time(0.0, 1.0),
      acceleration(-500.0, 500.0);
  Matrix M, C, K, C_fd, K_fd, M_reduced;
  for (int k = 0; k < 50; ++k) {
    // q0 in steps of about 0.4 rad from the assembly: each solve from the last (one branch).
    const State s = one_coordinate_state(time(rng), 0.4 * k + 0.1 * angle(rng), rate(rng));
    const Vector qdd = Vector::Constant(1, acceleration(rng));
    CAPTURE(k, s.t, s.q(0), s.qd(0), qdd(0));
    system.jacobians(s, qdd, M, C, K);
    richardson_jacobians(system, s, qdd, C_fd, K_fd);
    CHECK(relative(K, K_fd) <= 1e-8);
    CHECK(relative(C, C_fd) <= 1e-8);
    system.mass_matrix(s, M_reduced);
    CHECK(relative(M, M_reduced) <= 1e-14);
  }
}

}  // namespace

TEST_CASE("the loops' exact Jacobians agree with extrapolated differences of the residual",
          "[models][loops]") {
  SECTION("four-bar") {
    check_exact_loop_jacobians<gen::four_bar>(31u);
  }
  SECTION("implicit slider-crank") {
    check_exact_loop_jacobians<gen::slider_crank_implicit>(37u);
  }
}

TEST_CASE(
    "the implicit slider-crank's exact Jacobians and dynamics derivatives equal the explicit one's",
    "[models][loops]") {
  MultibodySystem explicit_(Model::from<gen::slider_crank_dependent>());
  MultibodySystem implicit(Model::from<gen::slider_crank_implicit>());
  REQUIRE(explicit_.exact_jacobians());
  REQUIRE(implicit.exact_jacobians());
  std::mt19937 rng(41u);
  std::uniform_real_distribution<double> angle(-pi, pi), rate(-50.0, 50.0), time(0.0, 1.0),
      acceleration(-2000.0, 2000.0);
  Matrix Me, Ce, Ke, Mi, Ci, Ki;
  for (int k = 0; k < 200; ++k) {
    const State s = one_coordinate_state(time(rng), angle(rng), rate(rng));
    const Vector qdd = Vector::Constant(1, acceleration(rng));
    CAPTURE(k, s.t, s.q(0), s.qd(0), qdd(0));
    implicit.reset_loops();  // the closed form's branch, as above
    explicit_.jacobians(s, qdd, Me, Ce, Ke);
    implicit.jacobians(s, qdd, Mi, Ci, Ki);
    CHECK(relative(Me, Mi) <= 1e-12);
    CHECK(relative(Ce, Ci) <= 1e-12);
    CHECK(relative(Ke, Ki) <= 1e-12);
    // The forward dynamics' derivatives, and M⁻¹, through them.
    DynamicsDerivatives de, di;
    explicit_.dynamics_derivatives(s, de, true);
    implicit.dynamics_derivatives(s, di, true);
    CHECK(relative(de.qdd, di.qdd) <= 1e-12);
    CHECK(relative(de.dqdd_dq, di.dqdd_dq) <= 1e-11);
    CHECK(relative(de.dqdd_dqd, di.dqdd_dqd) <= 1e-11);
    CHECK(relative(de.dqdd_dtau, di.dqdd_dtau) <= 1e-12);
  }
}

TEST_CASE("SmallLu's sparse path (large, sparse g_p) and dense path agree at random values",
          "[loops]") {
  std::mt19937 rng(47u);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // Six loops of three equations: each in its two own parameters and six shared.
  const int loops = 6, rows = 3, own = 2, shared = 6, n = loops * rows;
  RowMajor pattern = RowMajor::Zero(n, n);
  for (int l = 0; l < loops; ++l) {
    for (int i = l * rows; i < (l + 1) * rows; ++i) {
      for (int j = 0; j < own; ++j) pattern(i, l * own + j) = 1.0;
      for (int j = 0; j < shared; ++j) pattern(i, loops * own + j) = 1.0;
    }
  }
  SmallLu sparse, dense(false);
  for (int trial = 0; trial < 20; ++trial) {
    CAPTURE(trial);
    RowMajor A = pattern;
    for (int i = 0; i < n * n; ++i) A.data()[i] *= entry(rng);
    sparse.factor(A.data(), n);
    dense.factor(A.data(), n);
    REQUIRE(sparse.sparse());
    REQUIRE_FALSE(dense.sparse());
    CHECK(sparse.smallest_pivot_ratio() > 0);
    RowMajor B(n, 7);
    for (int i = 0; i < 7 * n; ++i) B.data()[i] = entry(rng);
    RowMajor Xs = B, Xd = B;
    sparse.solve_rows(Xs.data(), 7);
    dense.solve_rows(Xd.data(), 7);
    CHECK(max_abs(A * Xs - B) <= 1e-12 * (1 + max_abs(A) * max_abs(Xs)));
    CHECK(max_abs(Xs - Xd) <= 1e-11 * (1 + max_abs(Xd)));
    Vector b = B.col(0), ys = b, yd = b;
    sparse.solve_transposed_in_place(ys);
    dense.solve_transposed_in_place(yd);
    CHECK(max_abs(A.transpose() * ys - b) <= 1e-12 * (1 + max_abs(A) * max_abs(ys)));
    CHECK(max_abs(ys - yd) <= 1e-11 * (1 + max_abs(yd)));
  }
  // A dense matrix, or one of a loop's few equations, takes the dense path.
  RowMajor full(n, n), small(SmallLu::kDenseUpTo, SmallLu::kDenseUpTo);
  for (int i = 0; i < n * n; ++i) full.data()[i] = entry(rng);
  small.setZero();
  small.diagonal().setOnes();
  SmallLu lu_full, lu_small;
  lu_full.factor(full.data(), n);
  lu_small.factor(small.data(), SmallLu::kDenseUpTo);
  CHECK_FALSE(lu_full.sparse());
  CHECK_FALSE(lu_small.sparse());
}

TEST_CASE("SmallLu's schedule is kept along a trajectory, its factors those of a fresh LU",
          "[loops]") {
  std::mt19937 rng(53u);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // Block-arrow as the Stewart platform's g_p: six loops of three equations,
  // each in its two own parameters and six shared; one entry zero at the
  // start (as sin 0 at a home pose).
  const int loops = 6, rows = 3, own = 2, shared = 6, n = loops * rows;
  RowMajor start = RowMajor::Zero(n, n), rate = RowMajor::Zero(n, n);
  for (int l = 0; l < loops; ++l) {
    for (int i = l * rows; i < (l + 1) * rows; ++i) {
      for (int j = 0; j < own; ++j) start(i, l * own + j) = entry(rng), rate(i, l * own + j) = 1;
      for (int j = 0; j < shared; ++j) {
        start(i, loops * own + j) = entry(rng), rate(i, loops * own + j) = entry(rng);
      }
    }
  }
  start(4, loops * own + 1) = 0.0;
  SmallLu lu;
  const auto solves_as_fresh = [&](const RowMajor& A) {
    lu.factor(A.data(), n);
    SmallLu fresh;
    fresh.factor(A.data(), n);
    REQUIRE(lu.sparse());
    // (fresh's column order is A's, lu's the first A's: the same factors to rounding)
    CHECK(std::abs(lu.smallest_pivot_ratio() - fresh.smallest_pivot_ratio()) <=
          1e-12 * fresh.smallest_pivot_ratio());
    RowMajor B(n, 7);
    for (int i = 0; i < 7 * n; ++i) B.data()[i] = entry(rng);
    RowMajor X = B, Y = B;
    lu.solve_rows(X.data(), 7);
    fresh.solve_rows(Y.data(), 7);
    CHECK(max_abs(A * X - B) <= 1e-12 * (1 + max_abs(A) * max_abs(X)));
    CHECK(max_abs(X - Y) <= 1e-14 * (1 + max_abs(Y)));
    // The first 6 columns alone, in B's rows of 7 (both paths): the last untouched.
    SmallLu dense(false);
    dense.factor(A.data(), n);
    for (const SmallLu* by : {&lu, &dense}) {
      RowMajor Z = B;
      by->solve_rows(Z.data(), 6, 7);
      CHECK(max_abs(Z.leftCols(6) - X.leftCols(6)) <= 1e-12 * (1 + max_abs(X)));
      CHECK(Z.col(6) == B.col(6));
    }
    Vector b = B.col(0), x = b, y = b;
    lu.solve_transposed_in_place(x);
    fresh.solve_transposed_in_place(y);
    CHECK(max_abs(A.transpose() * x - b) <= 1e-12 * (1 + max_abs(A) * max_abs(x)));
    CHECK(max_abs(x - y) <= 1e-14 * (1 + max_abs(y)));
  };
  solves_as_fresh(start);
  REQUIRE(lu.schedules() == 1);
  // The zero entry becomes nonzero: outside the first pattern, the schedule is made again.
  solves_as_fresh(start + 1e-5 * rate);
  REQUIRE(lu.schedules() == 2);
  // Small steps along the trajectory keep it (its pivots stay the largest of their columns).
  for (int step = 2; step < 40; ++step) {
    CAPTURE(step);
    solves_as_fresh(start + 1e-5 * step * rate);
  }
  CHECK(lu.schedules() == 2);
  // A pivot no longer the largest of its column: factored anew, and right.
  RowMajor A = start + 4e-4 * rate;
  A.row(0).swap(A.row(1));
  A.row(0) *= 1e-3;
  solves_as_fresh(A);
  CHECK(lu.schedules() == 3);
  // A singular one is said to be (its pivot zero), then a regular one factors again.
  RowMajor singular = start + 4e-4 * rate;
  singular.row(2) = singular.row(1);
  lu.factor(singular.data(), n);
  CHECK(lu.smallest_pivot_ratio() < 1e-15);
  solves_as_fresh(start + 4e-4 * rate);
}

TEST_CASE("SmallLu solves as a direct product checks, transposed too, and flags a singular g_p",
          "[loops]") {
  std::mt19937 rng(43u);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    // Row-major, as the emitted g_p.
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A(n, n);
    for (int i = 0; i < n * n; ++i) A.data()[i] = entry(rng);
    SmallLu lu;
    lu.factor(A.data(), n);
    CHECK(lu.smallest_pivot_ratio() > 0);
    Matrix B(n, 3);
    for (int i = 0; i < 3 * n; ++i) B.data()[i] = entry(rng);
    Matrix X = B;
    lu.solve_in_place(X);
    CHECK(max_abs(A * X - B) <= 1e-12 * (1 + max_abs(A) * max_abs(X)));
    Vector b = B.col(0), y = b;
    lu.solve_transposed_in_place(y);
    CHECK(max_abs(A.transpose() * y - b) <= 1e-12 * (1 + max_abs(A) * max_abs(y)));
  }
  // Block-arrow, as the loops' g_p (each loop's rows: its own columns and
  // the shared ones, listed first): the columns reordered by sparsity and the
  // zeros skipped, the solves as the direct products say.
  for (const int loops : {1, 3, 6}) {
    CAPTURE(loops);
    const int own = 2, rows = 3, shared = loops * (rows - own), n = loops * rows;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A =
        Eigen::MatrixXd::Zero(n, n);
    for (int l = 0; l < loops; ++l) {
      for (int i = l * rows; i < (l + 1) * rows; ++i) {
        for (int j = 0; j < shared; ++j) A(i, j) = entry(rng);
        for (int j = 0; j < own; ++j) A(i, shared + l * own + j) = entry(rng);
      }
    }
    SmallLu lu;
    lu.factor(A.data(), n);
    CHECK(lu.smallest_pivot_ratio() > 0);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> B(n, 7);
    for (int i = 0; i < 7 * n; ++i) B.data()[i] = entry(rng);
    auto X = B;
    lu.solve_rows(X.data(), 7);
    CHECK(max_abs(A * X - B) <= 1e-12 * (1 + max_abs(A) * max_abs(X)));
    Vector b = B.col(0), x = b, y = b;
    lu.solve_in_place(x);
    CHECK(max_abs(x - X.col(0)) <= 1e-13 * (1 + max_abs(x)));
    lu.solve_transposed_in_place(y);
    CHECK(max_abs(A.transpose() * y - b) <= 1e-12 * (1 + max_abs(A) * max_abs(y)));
    // Refactored with other values (and a zero where the first had none).
    A(0, 0) = 0.0;
    A(n - 1, shared - 1) += 1.0;
    lu.factor(A.data(), n);
    X = B;
    lu.solve_rows(X.data(), 7);
    CHECK(max_abs(A * X - B) <= 1e-12 * (1 + max_abs(A) * max_abs(X)));
  }
  // Two equal rows.
  const double singular[4] = {1.0, 2.0, 1.0, 2.0};
  SmallLu lu;
  lu.factor(singular, 2);
  CHECK(lu.smallest_pivot_ratio() == 0.0);
}
