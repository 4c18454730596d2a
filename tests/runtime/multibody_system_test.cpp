#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <regex>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/pendulum.hpp"
#include "fixtures/rigid_body.hpp"
#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
using Catch::Matchers::Contains;
namespace fx = symdyn_fixtures;

namespace {

State random_rigid_body_state() {
  Vector q = random_vector(6, -1.0, 1.0);
  q(4) = uniform(-1.2, 1.2);  // away from gimbal lock
  return make_state(uniform(0, 1), q, random_vector(6, -3.0, 3.0));
}

}  // namespace

TEST_CASE("Mass matrix is symmetric positive definite at random states", "[runtime][system]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  MultibodySystem rb(Model::from<fx::rigid_body>());
  Matrix M;
  for (int trial = 0; trial < 1000; ++trial) {
    dp.mass_matrix(make_state(0, random_vector(2, -4, 4), random_vector(2, -4, 4)), M);
    CHECK((M - M.transpose()).cwiseAbs().maxCoeff() < 1e-14);
    CHECK(Eigen::SelfAdjointEigenSolver<Matrix>(M).eigenvalues().minCoeff() > 0.0);
    rb.mass_matrix(random_rigid_body_state(), M);
    CHECK((M - M.transpose()).cwiseAbs().maxCoeff() < 1e-14);
    CHECK(Eigen::SelfAdjointEigenSolver<Matrix>(M).eigenvalues().minCoeff() > 0.0);
  }
}

TEST_CASE("Double pendulum: assembled M and h equal Lagrange's closed form", "[runtime][system]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  Matrix M;
  Vector h;
  for (int trial = 0; trial < 500; ++trial) {
    const State s = make_state(0, random_vector(2, -4, 4), random_vector(2, -5, 5));
    const Lagrange L = double_pendulum_lagrange(s.q, s.qd);
    dp.mass_matrix_assembled(s, M);
    dp.bias_forces_assembled(s, h);
    CHECK((M - L.M).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((h - L.h).cwiseAbs().maxCoeff() < 1e-12);
    // The explicit accelerations solve Lagrange's equations.
    Vector qdd, yd;
    dp.accelerations(s, qdd, yd);
    const Vector expected = L.M.ldlt().solve(-L.h);
    CHECK((qdd - expected).cwiseAbs().maxCoeff() < 1e-10);
  }
}

TEST_CASE("Assembled and emitted equations agree", "[runtime][system]") {
  MultibodySystem a(Model::from<fx::double_pendulum_absolute>(), EquationsSource::assembled);
  MultibodySystem e(Model::from<fx::double_pendulum_absolute>(), EquationsSource::emitted);
  // An applied force so that the projection of loads is exercised on both paths.
  for (MultibodySystem* s : {&a, &e}) {
    s->add<CoordinateSpringDamper>("hinge", 1, 3.0, 0.4, 0.2);
    s->add<PointLoad>("push", BodyPoint{1, Vec3(0.5, 0, 0)}, Vec3(1.0, -2.0, 0.5), Vec3(0, 0, 0.3));
  }
  for (int trial = 0; trial < 500; ++trial) {
    const State s = make_state(uniform(0, 2), random_vector(2, -4, 4), random_vector(2, -5, 5));
    const SourceComparison c = compare_sources(a, s);
    CHECK(c.mass_matrix < 1e-10);
    CHECK(c.bias_forces < 1e-10);
    Vector qa, qe, yd, fa, fe, g;
    a.accelerations(s, qa, yd);
    e.accelerations(s, qe, yd);
    CHECK((qa - qe).cwiseAbs().maxCoeff() < 1e-10);
    const Vector qdd = random_vector(2, -10, 10);
    a.residual(s, qdd, yd, fa, g);
    e.residual(s, qdd, yd, fe, g);
    CHECK((fa - fe).cwiseAbs().maxCoeff() < 1e-10);
    // The residual vanishes at the explicit accelerations.
    a.residual(s, qa, yd, fa, g);
    CHECK(fa.cwiseAbs().maxCoeff() < 1e-10);
  }
}

TEST_CASE("Pendulum and spring-mass accelerations match their closed forms", "[runtime][system]") {
  MultibodySystem p(Model::from<fx::pendulum>());
  Vector qdd, yd;
  for (double length : {1.0, 2.5}) {
    p.set_parameter("length", length);
    for (int trial = 0; trial < 100; ++trial) {
      const State s = make_state(0, random_vector(1, -4, 4), random_vector(1, -5, 5));
      p.accelerations(s, qdd, yd);
      // (I_zz + m h^2) qdd = -m g h cos(theta), h = l/2
      const double h = length / 2.0, I = length * length / 12.0;
      CHECK(qdd(0) == Approx(-9.81 * h * std::cos(s.q(0)) / (I + h * h)).epsilon(1e-13));
    }
  }
  MultibodySystem sm(Model::from<fx::spring_mass>());
  const double k = 4.0 * std::numbers::pi * std::numbers::pi;
  sm.add<PointSpringDamper>("spring", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                            k, 2.0);
  for (double q : {0.3, 1.0, 1.7, 4.0}) {
    sm.accelerations(make_state(0, Vector::Constant(1, q), Vector::Constant(1, 0.5)), qdd, yd);
    CHECK(qdd(0) == Approx(-k * (q - 1.0)).margin(1e-12));
  }
}

TEST_CASE("Rigid body: gyroscopic terms satisfy Euler's equations", "[runtime][system]") {
  MultibodySystem rb(Model::from<fx::rigid_body>());
  const Eigen::DiagonalMatrix<double, 3> I(0.1, 0.2, 0.25);
  Vector qdd, yd;
  for (int trial = 0; trial < 300; ++trial) {
    const State s = random_rigid_body_state();
    rb.accelerations(s, qdd, yd);
    Vector fres, g;
    rb.residual(s, qdd, yd, fres, g);  // leaves the kinematics at qdd in the workspace
    const Kinematics& k = rb.kinematics();
    CHECK((k.a(0) - Vec3(0, 0, -9.81)).norm() < 1e-12);
    // Body axes: I dw_b + w_b x (I w_b) = 0 for a free body.
    const Mat3 R = k.R(0);
    const Vec3 wb = R.transpose() * k.w(0);
    const Vec3 dwb = R.transpose() * k.dw(0);
    CHECK((I * dwb + wb.cross(I * wb)).norm() < 1e-10 * (1.0 + wb.squaredNorm()));
    // Angular momentum about G is conserved: central difference along the motion.
    const double h = 1e-4;
    auto momentum_at = [&](double sign) {
      State p = s;
      p.q = s.q + sign * h * s.qd + 0.5 * h * h * qdd;
      p.qd = s.qd + sign * h * qdd;
      rb.evaluate_kinematics(p);
      const Mat3 Rp = rb.kinematics().R(0);
      return Vec3(Rp * (I * (Rp.transpose() * rb.kinematics().w(0))));
    };
    const Vec3 dL = (momentum_at(1.0) - momentum_at(-1.0)) / (2 * h);
    CHECK(dL.norm() < 1e-5 * (1.0 + s.qd.squaredNorm()));
  }
}

TEST_CASE("Jacobians: exact M, K and C by differences", "[runtime][system]") {
  MultibodySystem p(Model::from<fx::pendulum>());
  p.add<CoordinateSpringDamper>("hinge", 0, 0.0, 0.7);
  Matrix M, C, K;
  for (double theta : {-2.0, 0.3, 1.1}) {
    const State s = make_state(0, Vector::Constant(1, theta), Vector::Constant(1, 0.4));
    p.jacobians(s, Vector::Constant(1, 2.0), M, C, K);
    // f = (I + m h^2) qdd + m g h cos(theta) + c qd
    CHECK(M(0, 0) == Approx(1.0 / 12.0 + 0.25).epsilon(1e-14));
    CHECK(K(0, 0) == Approx(-9.81 * 0.5 * std::sin(theta)).epsilon(1e-7));
    CHECK(C(0, 0) == Approx(0.7).epsilon(1e-7));
  }
}

TEST_CASE("Extra states: a DC motor driving the pendulum", "[runtime][system]") {
  // L di/dt = V - R i - k_e qd; torque k_t i on theta.
  const double L = 0.01, Rm = 2.0, ke = 0.1, V = 12.0;
  MultibodySystem p(Model::from<fx::pendulum>());
  p.add<CoordinateForce>("motor", 0,
                         [&](double, double, double, const State& s) { return ke * s.y(0); });
  p.set_extra_states({"current"}, Vector::Constant(1, 0.5),
                     [&](const State& s, const Kinematics&, Eigen::Ref<Vector> yd) {
                       yd(0) = (V - Rm * s.y(0) - ke * s.qd(0)) / L;
                     });
  CHECK(p.num_extra_states() == 1);
  CHECK(p.extra_state_name(0) == "current");
  State s = p.initial_state();
  CHECK(s.y(0) == 0.5);
  s.qd(0) = 3.0;
  Vector qdd, yd, f, g;
  p.accelerations(s, qdd, yd);
  CHECK(yd(0) == Approx((V - Rm * 0.5 - ke * 3.0) / L));
  const double expected = (ke * 0.5 - 9.81 * 0.5 * std::cos(0.3)) / (1.0 / 12.0 + 0.25);
  CHECK(qdd(0) == Approx(expected).epsilon(1e-13));
  p.residual(s, qdd, yd, f, g);
  CHECK(std::abs(f(0)) < 1e-12);
  CHECK(std::abs(g(0)) < 1e-9);
  p.residual(s, qdd, Vector::Zero(1), f, g);
  CHECK(g(0) == Approx(-yd(0)));
}

TEST_CASE("Singular mass matrix is a NumericError naming time and state",
          "[runtime][system][errors]") {
  MultibodySystem rb(Model::from<fx::rigid_body>());
  Vector q(6);
  q << 0, 0, 1, 0.2, std::numbers::pi / 2, 0.1;
  Vector qdd, yd;
  CHECK_THROWS_MATCHES(
      rb.accelerations(make_state(0.5, q, Vector::Zero(6)), qdd, yd), NumericError,
      Catch::Matchers::Predicate<std::exception>(
          [](const std::exception& e) {
            const std::string m = e.what();
            return m.find(
                       "t = 0.5: mass matrix is singular or indefinite: coordinates 'yaw' (0.71) "
                       "and 'roll' "
                       "(0.71) move the bodies the same way") == 0 &&
                   m.find("pitch = 1.5707963267948966") != std::string::npos;
          },
          "message names the time, the coordinates locked together and the pitch"));
  // A micro-radian from the lock the inertia left is tiny but real: solved.
  q(4) = std::numbers::pi / 2 - 1e-6;
  REQUIRE_NOTHROW(rb.accelerations(make_state(0.5, q, Vector::Zero(6)), qdd, yd));
  CHECK(qdd.allFinite());
  // But its pivot, 1e-12 of its diagonal, cost qdd more than half its digits: a
  // warning, in coordinate names (this model names no angle sequence).
  REQUIRE(rb.warnings().size() == 1);
  const std::string& w = rb.warnings().front();
  CAPTURE(w);
  CHECK(w.rfind("t = 0.5: the mass matrix is nearly singular, the accelerations have lost more "
                "than half their digits: the smallest pivot of its factorization is ",
                0) == 0);
  CHECK(std::regex_search(
      w, std::regex(R"(weakest direction '(yaw|roll)' \(-?0\.71\), '(yaw|roll)' \(-?0\.71\))")));
  // Away from the lock: no warning.
  MultibodySystem upright(Model::from<fx::rigid_body>());
  q(4) = 0.3;
  upright.accelerations(make_state(0.5, q, Vector::Zero(6)), qdd, yd);
  CHECK(upright.warnings().empty());
}

TEST_CASE("Non-finite values are NumericErrors naming time, quantity and culprit",
          "[runtime][system][errors]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  Vector qdd, yd;
  Vector qnan(2);
  qnan << nan, 0.0;
  CHECK_THROWS_MATCHES(
      dp.accelerations(make_state(1.5, qnan, Vector::Zero(2)), qdd, yd), NumericError,
      Catch::Matchers::Message("t = 1.5: coordinate 'q0' is not finite (q = nan, qd = 0)"));
  Vector q(2);
  q << 0.1, 0.2;
  Vector qd(2);
  qd << 0.0, INFINITY;
  CHECK_THROWS_WITH(dp.accelerations(make_state(2, q, qd), qdd, yd),
                    "t = 2: coordinate 'q1' is not finite (q = 0.2, qd = inf)");
  // A force element producing NaN is named with the body.
  dp.add<PointLoad>("bad", BodyPoint{1, Vec3::Zero()},
                    [&](const State&, const Kinematics&, Vec3& f, Vec3&) { f(0) = nan; });
  CHECK_THROWS_WITH(dp.accelerations(make_state(3, q, Vector::Zero(2)), qdd, yd),
                    "t = 3: load 'bad': force or moment on body 'rod2' is not finite");
  MultibodySystem p(Model::from<fx::pendulum>());
  p.add<CoordinateForce>("broken", 0, [nan](double, double, double, const State&) { return nan; });
  CHECK_THROWS_WITH(
      p.accelerations(p.initial_state(), qdd, yd),
      "t = 0: coordinate force 'broken': generalized force on coordinate 'theta' is not finite");
}

namespace nan_model {
// A model whose velocity of body "b" turns NaN for q < 0 (sqrt of a negative).
void inertia(const double*, double* m, double* I) {
  m[0] = 1.0;
  for (int k = 0; k < 9; ++k) I[k] = (k % 4 == 0) ? 1.0 : 0.0;
}
void accelerations(double, const double* q, const double* qd, const double* qdd, const double*,
                   double* R, double* x, double* v, double* w, double* a, double* dw) {
  for (int k = 0; k < 9; ++k) R[k] = (k % 4 == 0) ? 1.0 : 0.0;
  for (int k = 0; k < 3; ++k) x[k] = v[k] = w[k] = a[k] = dw[k] = 0.0;
  x[0] = q[0];
  v[0] = std::sqrt(q[0]) * qd[0];
  a[0] = qdd[0];
}
void velocities(double t, const double* q, const double* qd, const double* p, double* R, double* x,
                double* v, double* w) {
  double a[3], dw[3];
  accelerations(t, q, qd, qd, p, R, x, v, w, a, dw);
}
void partials(double, const double*, const double*, double* dv, double* dw) {
  dv[0] = 1.0;
  dv[1] = dv[2] = dw[0] = dw[1] = dw[2] = 0.0;
}
}  // namespace nan_model

TEST_CASE("A non-finite kinematic quantity names the body", "[runtime][system][errors]") {
  ModelDescription d;
  d.model = "broken";
  d.nq = 1;
  d.nbody = 1;
  d.q_names = {"s"};
  d.q_initial = {-1.0};
  d.qd_initial = {1.0};
  d.body_names = {"b"};
  d.reference_body = {-1};
  d.inertia = nan_model::inertia;
  d.velocities = nan_model::velocities;
  d.accelerations = nan_model::accelerations;
  d.partial_velocities = nan_model::partials;
  MultibodySystem sys{Model(d)};
  CHECK_THROWS_WITH(sys.energies(sys.initial_state()),
                    "t = 0: body 'b': velocity v is not finite at q = (s = -1), qd = (1)");
}

TEST_CASE("State sizes are checked", "[runtime][system][errors]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  Vector qdd, yd;
  CHECK_THROWS_WITH(dp.accelerations(make_state(0, Vector::Zero(3), Vector::Zero(2)), qdd, yd),
                    "model 'double_pendulum': a state with 3 q, 2 qd, 0 y given; expected 2, 2, 0");
}
