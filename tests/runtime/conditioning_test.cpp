// A mass matrix that has lost half its digits is reported once, with the time
// and the cause; a gimbal lock is named as the angle sequence it is.

#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "trike.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;

constexpr double kHalfPi = std::numbers::pi / 2;

// The trike's chassis pitch (q[4], of its Z-Y-X yaw, pitch, roll q[3..5]) at
// pi/2 - offset, rolling at 5 m/s with a pitch rate.
State trike_pitched(const MultibodySystem& sys, double offset, double pitch_rate = 0.0) {
  State s = sys.initial_state();
  s.q[4] = kHalfPi - offset;
  s.qd[4] = pitch_rate;
  return s;
}

// M's smallest pivot against its diagonal at s (the measure of the warning).
double pivot_ratio(MultibodySystem& sys, const State& s) {
  Matrix M;
  sys.mass_matrix(s, M);
  SpdSolver solver(static_cast<int>(M.rows()));
  solver.factor(M);
  return solver.smallest_pivot_ratio();
}

}  // namespace

TEST_CASE(
    "the trike 1e-6 rad from its Euler angles' singularity: one warning naming the sequence and "
    "the time; none where M is well conditioned",
    "[multibody][conditioning]") {
  for (const bool recursive : {true, false}) {  // the articulated-body algorithm, and M
    CAPTURE(recursive);
    MultibodySystem sys(Model::from<symdyn_generated::trike>());
    sys.set_recursive(recursive);
    Vector qdd, yd;
    // 1e-2 rad away: M's pivot is 1e-4 of its diagonal, qdd keeps most of its digits.
    State s = trike_pitched(sys, 1e-2);
    CHECK(pivot_ratio(sys, s) > 1e-6);
    sys.accelerations(s, qdd, yd);
    CHECK(sys.warnings().empty());
    // 1e-6 rad away: the pivot falls as the square of the distance, to about 1e-12.
    s = trike_pitched(sys, 1e-6);
    s.t = 0.75;
    CHECK(pivot_ratio(sys, s) < MultibodySystem::kConditionWarning);
    sys.accelerations(s, qdd, yd);
    REQUIRE(sys.warnings().size() == 1);
    const std::string& w = sys.warnings().front();
    CAPTURE(w);
    CHECK(w.rfind(
              "t = 0.75: the mass matrix is nearly singular, the accelerations have lost more "
              "than half their digits: coordinates 'yaw', 'pitch', 'roll' of body 'chassis' form a "
              "Z-Y-X angle sequence 1e-06 rad from its singular configuration pitch = 90 deg",
              0) == 0);
    // Once: further evaluations add nothing, until cleared.
    sys.accelerations(s, qdd, yd);
    Vector f, g;
    sys.residual(s, qdd, yd, f, g);
    CHECK(sys.warnings().size() == 1);
    sys.clear_warnings();
    sys.residual(s, qdd, yd, f, g);  // the implicit integrators' form warns too
    CHECK(sys.warnings().size() == 1);
  }
}

TEST_CASE("a normal run of the trike gives no warning", "[multibody][conditioning]") {
  for (const char* name : {"dopri5", "newmark"}) {
    CAPTURE(name);
    MultibodySystem sys(Model::from<symdyn_generated::trike>());
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = 1e-6;
    make_integrator(name, o)->integrate(sys, sys.initial_state(), 0.3);
    CHECK(sys.warnings().empty());
  }
}

TEST_CASE(
    "newmark into the trike's gimbal lock: names the angle sequence, suggests no dependent "
    "parameter (the trike has none)",
    "[integrator][errors][conditioning]") {
  MultibodySystem sys(Model::from<symdyn_generated::trike>());
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = 1e-8;
  // Pitching up at 1 rad/s from 1e-4 rad below the lock, yawing at 0.1 rad/s:
  // the Newton iteration diverges at the lock, whatever the step.
  State s = trike_pitched(sys, 1e-4, 1.0);
  s.qd[3] = 0.1;
  std::string m;
  try {
    make_integrator("newmark", o)->integrate(sys, s, 0.2);
  } catch (const NumericError& e) {
    m = e.what();
  }
  CAPTURE(m);
  REQUIRE_FALSE(m.empty());
  CHECK(m.find("dependent parameter") == std::string::npos);
  CHECK(m.find("Newton iteration diverges") != std::string::npos);
  CHECK(
      m.find("near a singular configuration: coordinates 'yaw', 'pitch', 'roll' of body 'chassis' "
             "form a Z-Y-X angle sequence") != std::string::npos);
  CHECK(sys.warnings().size() == 1);
}
