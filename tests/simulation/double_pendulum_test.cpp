// The generated double pendulum (docs/models.md 1) against a hand-written residual,
// energy conservation, the small-oscillation frequencies and a static
// equilibrium, each against a closed form or an independent computation.

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "double_pendulum_absolute.hpp"
#include "double_pendulum_relative.hpp"
#include "runtime/test_util.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/statics.hpp>

namespace {

using namespace symdyn::runtime;
using symdyn::runtime::test::double_pendulum_lagrange;
namespace gen = symdyn_generated;

constexpr double g = 9.81;
constexpr double Izz = 0.083333333333333333;  // each rod about its G, as in docs/models.md

// Lagrange's equations M(q) qdd + h(q, qd) = 0, written by hand
// (tests/runtime/test_util.hpp), as a residual DynamicSystem.
class HandWrittenPendulum : public DynamicSystem {
 public:
  int num_coordinates() const override { return 2; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    const auto L = double_pendulum_lagrange(s.q, s.qd);
    qdd = L.M.ldlt().solve(-L.h);
    yd.resize(0);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    const auto L = double_pendulum_lagrange(s.q, s.qd);
    f = L.M * qdd + L.h;
    g.resize(0);
  }
};

// q at t = 0, 0.1, ..., t_end (dopri5, tolerance tol), from horizontal at rest.
std::vector<Vector> trajectory(DynamicSystem& system, double t_end, double tol) {
  IntegratorOptions o;
  o.relative_tolerance = tol;
  o.absolute_tolerance = tol;
  o.output_interval = 0.1;
  std::vector<Vector> q;
  o.on_output = [&q](const State& s, const Vector&, const Vector&) { q.push_back(s.q); };
  State s0{0.0, Vector::Zero(2), Vector::Zero(2), Vector()};
  make_integrator("dopri5", o)->integrate(system, s0, t_end);
  return q;
}

double max_difference(const std::vector<Vector>& a, const std::vector<Vector>& b) {
  REQUIRE(a.size() == b.size());
  double d = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) d = std::max(d, (a[k] - b[k]).cwiseAbs().maxCoeff());
  return d;
}

}  // namespace

TEST_CASE("double pendulum three ways: hand-written, generated absolute, generated relative",
          "[models][double_pendulum]") {
  // 3 s of the chaotic swing at tolerance 1e-12: they agree to ~1e-13 (q
  // spans radians); 1e-10 leaves room for round-off, which grows with time.
  const double t_end = 3.0, tol = 1e-12;
  HandWrittenPendulum hand;
  MultibodySystem absolute(Model::from<gen::double_pendulum_absolute>(), EquationsSource::emitted);
  MultibodySystem relative(Model::from<gen::double_pendulum_relative>(), EquationsSource::emitted);
  MultibodySystem assembled(Model::from<gen::double_pendulum_relative>(),
                            EquationsSource::assembled);
  const auto q_hand = trajectory(hand, t_end, tol);
  REQUIRE(q_hand.size() == 31);
  CHECK(q_hand.back().cwiseAbs().maxCoeff() > 0.5);  // it has moved
  CHECK(max_difference(q_hand, trajectory(absolute, t_end, tol)) < 1e-10);
  CHECK(max_difference(q_hand, trajectory(relative, t_end, tol)) < 1e-10);
  CHECK(max_difference(q_hand, trajectory(assembled, t_end, tol)) < 1e-10);
}

TEST_CASE("generated double pendulum conserves energy to 1e-9 over 10 s",
          "[models][double_pendulum]") {
  // Released horizontal at rest, E(0) = 0: the drift is measured against the
  // pendulum's energy scale, the largest kinetic energy reached.
  for (const char* name : {"dopri5", "cvode"}) {
    CAPTURE(name);
    MultibodySystem dp(Model::from<gen::double_pendulum_absolute>(), EquationsSource::emitted);
    IntegratorOptions o;
    o.relative_tolerance = std::string(name) == "dopri5" ? 1e-12 : 1e-13;
    o.absolute_tolerance = o.relative_tolerance;
    o.output_interval = 0.01;
    double drift = 0.0, t_max = 0.0;
    o.on_output = [&](const State& s, const Vector&, const Vector&) {
      const Energies e = dp.energies(s);
      drift = std::max(drift, std::abs(e.total()));
      t_max = std::max(t_max, e.kinetic);
    };
    const State end = make_integrator(name, o)->integrate(dp, dp.initial_state(), 10.0);
    CHECK(end.t == 10.0);
    CHECK(t_max > 10.0);  // of the order of m g l: the pendulum swung
    CHECK(drift / t_max < 1e-9);
  }
}

TEST_CASE("small oscillations of the hanging double pendulum: two closed-form frequencies",
          "[models][double_pendulum]") {
  // About q = (-pi/2, 0) (both rods down), with a = l1 = 1, b = l2/2 = 1/2,
  // c = l1/2 = 1/2, unit masses: M = [[2 I + c^2 + (a + b)^2, I + b^2 + a b],
  // [I + b^2 + a b, I + b^2]], K = g [[c + a + b, b], [b, b]] (Hessian of V),
  // and det(K - w^2 M) = 0 is a quadratic in w^2.
  const double a = 1.0, b = 0.5, c = 0.5;
  const double M00 = 2 * Izz + c * c + (a + b) * (a + b), M01 = Izz + b * b + a * b,
               M11 = Izz + b * b;
  const double K00 = g * (c + a + b), K01 = g * b, K11 = g * b;
  const double A = M00 * M11 - M01 * M01;
  const double B = -(M00 * K11 + M11 * K00 - 2 * M01 * K01);
  const double C = K00 * K11 - K01 * K01;
  const double disc = std::sqrt(B * B - 4 * A * C);
  const double f_low = std::sqrt((-B - disc) / (2 * A)) / (2 * std::numbers::pi);
  const double f_high = std::sqrt((-B + disc) / (2 * A)) / (2 * std::numbers::pi);

  for (auto source : {EquationsSource::emitted, EquationsSource::assembled}) {
    MultibodySystem dp(Model::from<gen::double_pendulum_relative>(), source);
    State hanging = dp.initial_state();
    hanging.q << -std::numbers::pi / 2, 0.0;
    const auto m = modes(linearize(dp, hanging));
    REQUIRE(m.size() == 2);
    CHECK(m[0].natural_frequency_hz == Approx(f_low).epsilon(1e-6));
    CHECK(m[1].natural_frequency_hz == Approx(f_high).epsilon(1e-6));
    CHECK(std::abs(m[0].damping_ratio) < 1e-6);
    CHECK(std::abs(m[1].damping_ratio) < 1e-6);
  }
}

TEST_CASE("static equilibrium of the double pendulum held by torsion springs",
          "[models][double_pendulum]") {
  // Springs Q_j = -k_j (q_j - r_j) on both joints. Choosing the free angles
  // r = q* + K^-1 dV/dq(q*) (dV/dq by hand: test_util.hpp) makes q* the
  // equilibrium in closed form; the solver starts from horizontal.
  const Vector q_star = (Vector(2) << -0.4, 0.7).finished();
  const double k0 = 60.0, k1 = 25.0;
  const auto L = double_pendulum_lagrange(q_star, Vector::Zero(2));
  const double r0 = q_star(0) + L.dV(0) / k0, r1 = q_star(1) + L.dV(1) / k1;
  for (auto source : {EquationsSource::emitted, EquationsSource::assembled}) {
    MultibodySystem dp(Model::from<gen::double_pendulum_absolute>(), source);
    dp.add<CoordinateSpringDamper>("shoulder", 0, k0, 1.0, r0);
    dp.add<CoordinateSpringDamper>("elbow", 1, k1, 1.0, r1);
    StaticsOptions o;
    o.tolerance = 1e-12;
    const StaticsReport r = solve_statics(dp, dp.initial_state(), o);
    CHECK(std::abs(r.state.q(0) - q_star(0)) < 1e-9);
    CHECK(std::abs(r.state.q(1) - q_star(1)) < 1e-9);
    CHECK(r.iterations > 1);
  }
}
