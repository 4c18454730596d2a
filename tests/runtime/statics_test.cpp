#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>
#include <symdyn/runtime/statics.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
using Catch::Matchers::Contains;
namespace fx = symdyn_fixtures;

namespace {
const double k2pi = 4.0 * std::numbers::pi * std::numbers::pi;
}

TEST_CASE("Statics of the spring-loaded mass: q = 1", "[runtime][statics]") {
  SECTION("point-to-point spring, EasyDyn's 100 M + K") {
    MultibodySystem sm(Model::from<fx::spring_mass>());
    sm.add<PointSpringDamper>("spring", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                              k2pi, 2.0, 3.0);
    const StaticsReport r = solve_statics(sm, sm.initial_state());
    CHECK(std::abs(r.state.q(0) - 1.0) < 1e-8);
    CHECK(r.residual_norm < 1e-6);
    CHECK(r.iterations > 1);
    CHECK_THAT(r.summary(), Contains("static equilibrium after"));
  }
  SECTION("generalized spring, plain Newton converges at once on a linear problem") {
    MultibodySystem sm(Model::from<fx::spring_mass>());
    sm.add<CoordinateSpringDamper>("spring", 0, k2pi, 0.0, 2.0);
    StaticsOptions o;
    o.mass_weight = 0.0;
    const StaticsReport r = solve_statics(sm, sm.initial_state(), o);
    CHECK(r.state.q(0) == Approx(1.0).epsilon(1e-12));
    CHECK(r.iterations <= 3);
  }
}

TEST_CASE("Statics of the double pendulum with torsion springs", "[runtime][statics]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  dp.add<CoordinateSpringDamper>("k0", 0, 60.0, 0.0, 0.0);
  dp.add<CoordinateSpringDamper>("k1", 1, 25.0, 0.0, 0.0);
  State start = dp.initial_state();
  StaticsOptions tight;
  tight.tolerance = 1e-10;
  const StaticsReport r = solve_statics(dp, start, tight);
  // Equilibrium: k q + dV/dq = 0 (Lagrange's potential gradient).
  const Lagrange L = double_pendulum_lagrange(r.state.q, Vector::Zero(2));
  CHECK(std::abs(60.0 * r.state.q(0) + L.dV(0)) < 1e-6);
  CHECK(std::abs(25.0 * r.state.q(1) + L.dV(1)) < 1e-6);
  CHECK(r.state.q(0) < -0.1);  // it sags

  SECTION("a locked coordinate keeps its value") {
    StaticsOptions o = tight;
    o.locked = {0};
    start.q(0) = 0.3;
    const StaticsReport l = solve_statics(dp, start, o);
    CHECK(l.state.q(0) == 0.3);
    const Lagrange Ll = double_pendulum_lagrange(l.state.q, Vector::Zero(2));
    CHECK(std::abs(25.0 * l.state.q(1) + Ll.dV(1)) < 1e-6);
  }
}

TEST_CASE("Statics: line search rescues Newton on a saturating force", "[runtime][statics]") {
  // f(q) = -(2 pi)^2 atan(3 - q): plain Newton from q = 1 diverges
  // (|3 - q| > 1.39), backtracking on |f| converges to q = 3.
  MultibodySystem sm(Model::from<fx::spring_mass>());
  sm.add<CoordinateForce>("saturating", 0, [](double, double q, double, const State&) {
    return k2pi * (1.0 + std::atan(3.0 - q));
  });
  State start = sm.initial_state();
  start.q(0) = 1.0;
  StaticsOptions o;
  o.mass_weight = 0.0;
  o.max_iterations = 50;
  const StaticsReport r = solve_statics(sm, start, o);
  CHECK(r.state.q(0) == Approx(3.0).epsilon(1e-10));
  o.line_search = false;
  CHECK_THROWS_AS(solve_statics(sm, start, o), NumericError);
}

TEST_CASE("Statics reports non-convergence", "[runtime][statics][errors]") {
  // Gravity and nothing to hold the mass: no equilibrium.
  MultibodySystem sm(Model::from<fx::spring_mass>());
  StaticsOptions o;
  o.max_iterations = 50;
  CHECK_THROWS_WITH(solve_statics(sm, sm.initial_state(), o),
                    Contains("statics: no equilibrium found after 50 iterations (|f| = 3.948e+01"));
  o.mass_weight = 0.0;  // K = 0: the plain Newton matrix is singular
  CHECK_THROWS_WITH(solve_statics(sm, sm.initial_state(), o),
                    Contains("statics: iteration matrix 0·M + K is singular at iteration 1"));
}
