// The runtime computes what the attached force elements read and nothing
// more, from one emitted call, without allocating: checked on every
// generated model against the assembled source (EasyDyn's way, from the
// separate emitted kinematics and partial velocities).

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "all_models.hpp"
#include "allocation_count.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace {

using namespace symdyn::runtime;

// States near the initial one where the kinematics are finite (closed loops).
std::vector<State> states_near_initial(MultibodySystem& system, int count) {
  std::mt19937 rng(1234u + static_cast<unsigned>(system.model().nq()));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<State> states;
  for (int attempt = 0; attempt < 100 * count && static_cast<int>(states.size()) < count;
       ++attempt) {
    State s = system.initial_state();
    s.t = 0.5 * (1.0 + u(rng));
    for (int j = 0; j < system.num_coordinates(); ++j) {
      s.q(j) += 0.1 * u(rng);
      s.qd(j) += u(rng);
    }
    try {
      system.evaluate_kinematics(s);
      states.push_back(s);
    } catch (const NumericError&) {
    }
  }
  REQUIRE(static_cast<int>(states.size()) == count);
  return states;
}

// Elements of each level on the last body and the first coordinate.
enum class Elements { none, coordinate, positions, velocities };

void attach(MultibodySystem& system, Elements which) {
  const int last = system.model().nbody() - 1;
  const BodyPoint tip{last, Vec3(0.1, 0.05, -0.02)};
  const BodyPoint anchor{ground, Vec3(0.3, -0.2, 0.1)};
  switch (which) {
    case Elements::none:
      break;
    case Elements::coordinate:
      system.add<CoordinateSpringDamper>("q0 spring", 0, 30.0, 2.0, 0.1);
      break;
    case Elements::positions:
      system.add<CoordinateSpringDamper>("q0 spring", 0, 30.0, 2.0, 0.1);
      system.add<PointSpringDamper>("spring", anchor, tip, 200.0, 0.05);
      break;
    case Elements::velocities:
      system.add<PointSpringDamper>("spring", anchor, tip, 200.0, 0.05);
      system.add<PointSpringDamper>("damper", anchor, tip, 0.0, 0.0, 15.0);
      break;
  }
}

KinematicsLevel expected_level(Elements which) {
  switch (which) {
    case Elements::positions:
      return KinematicsLevel::positions;
    case Elements::velocities:
      return KinematicsLevel::velocities;
    default:
      return KinematicsLevel::none;
  }
}

double max_abs(const Vector& v) {
  return v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace

TEMPLATE_LIST_TEST_CASE(
    "at each kinematics level the emitted source's qdd and residual equal the assembled ones",
    "[models][lean]", symdyn_test::all_models) {
  for (Elements which :
       {Elements::none, Elements::coordinate, Elements::positions, Elements::velocities}) {
    MultibodySystem emitted(Model::from<TestType>());
    MultibodySystem assembled(Model::from<TestType>(), EquationsSource::assembled);
    INFO("model " << emitted.model().name() << " " << emitted.model().variant() << ", elements "
                  << static_cast<int>(which));
    REQUIRE(emitted.source() ==
            EquationsSource::emitted);  // the default when the model has its equations
    attach(emitted, which);
    attach(assembled, which);
    CHECK(emitted.kinematics_level() == expected_level(which));
    Vector qdd_e, qdd_a, yd, f, g;
    for (const State& s : states_near_initial(assembled, 10)) {
      emitted.accelerations(s, qdd_e, yd);
      assembled.accelerations(s, qdd_a, yd);
      CHECK(max_abs(qdd_e - qdd_a) <= 1e-8 * (1.0 + max_abs(qdd_a)));
      emitted.residual(s, qdd_a, yd, f, g);
      Vector scale;
      assembled.residual(s, Vector::Zero(qdd_a.size()), yd, scale, g);
      CHECK(max_abs(f) <= 1e-8 * (1.0 + max_abs(scale)));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("accelerations and residuals allocate nothing after the first call",
                        "[models][lean]", symdyn_test::all_models) {
  if (!symdyn_test::allocation_count()) return;  // not countable under AddressSanitizer
  for (Elements which :
       {Elements::none, Elements::coordinate, Elements::positions, Elements::velocities}) {
    MultibodySystem system(Model::from<TestType>());
    attach(system, which);
    INFO("model " << system.model().name() << " " << system.model().variant() << ", elements "
                  << static_cast<int>(which));
    const std::vector<State> states = states_near_initial(system, 4);
    Vector qdd, yd, f, g;
    system.accelerations(states[0], qdd, yd);
    system.residual(states[0], qdd, yd, f, g);
    const std::size_t before = *symdyn_test::allocation_count();
    for (const State& s : states) {
      system.accelerations(s, qdd, yd);
      system.residual(s, qdd, yd, f, g);
    }
    CHECK(*symdyn_test::allocation_count() - before == 0);
  }
}

// The emitted path checks the state's values with the result's, after the
// evaluation: a NaN or an infinity anywhere in the state, even in a coordinate M and
// h do not depend on, is still reported as the state's, naming the coordinate.
TEMPLATE_LIST_TEST_CASE("accelerations name a non-finite state value before anything else",
                        "[models][lean]", symdyn_test::all_models) {
  MultibodySystem system(Model::from<TestType>());
  const State good = states_near_initial(system, 1)[0];
  Vector qdd, yd;
  State bad = good;
  bad.t = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(system.accelerations(bad, qdd, yd),
                    Catch::Matchers::Contains("time is not finite"));
  for (int j = 0; j < system.num_coordinates(); ++j) {
    const std::string name = "coordinate '" + system.model().q_names()[j] + "' is not finite";
    for (bool rate : {false, true}) {
      bad = good;
      (rate ? bad.qd : bad.q)(j) =
          rate ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
      INFO(system.model().name() << " " << system.model().variant() << ": " << name
                                 << (rate ? ", qd" : ", q"));
      CHECK_THROWS_AS(system.accelerations(bad, qdd, yd), NumericError);
      CHECK_THROWS_WITH(system.accelerations(bad, qdd, yd), Catch::Matchers::Contains(name));
    }
  }
  REQUIRE_NOTHROW(system.accelerations(good, qdd, yd));
  CHECK(qdd.allFinite());
}

TEST_CASE("a force element that reads no kinematics but pushes a body is refused, named",
          "[models][lean]") {
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
  system.add<UserForce>(
      "push",
      [](const State&, const Kinematics&, Loads& loads) {
        loads.add_force(1, Vec3(1.0, 0.0, 0.0));
      },
      KinematicsLevel::none);
  CHECK(system.kinematics_level() == KinematicsLevel::none);
  Vector qdd, yd;
  CHECK_THROWS_WITH(
      system.accelerations(system.initial_state(), qdd, yd),
      Catch::Matchers::Contains("user force 'push' applies a force on a body but declares that it "
                                "reads no kinematics"));
}

TEST_CASE("integration steps allocate nothing: a run's allocations do not grow with its length",
          "[models][lean]") {
  if (!symdyn_test::allocation_count()) return;  // not countable under AddressSanitizer
  // Outputs at every step, and interpolated between steps (dense output).
  for (const double interval : {0.0, 0.01}) {
    for (const std::string& name : integrator_names()) {
      MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
      State start = system.initial_state();
      start.q << 0.5, -0.3;
      IntegratorOptions o;
      o.relative_tolerance = o.absolute_tolerance = 1e-8;
      o.output_interval = interval;
      o.on_output = [](const State&, const Vector&, const Vector&) {};
      if (name == "rk4" || name == "midpoint") o.initial_step = 1e-3;
      make_integrator(name, o)->integrate(system, start, 1.0);  // the system's workspaces sized
      std::size_t allocations[2] = {0, 0};
      long steps[2] = {0, 0};
      for (int k = 0; k < 2; ++k) {
        auto integrator = make_integrator(name, o);
        const std::size_t before = *symdyn_test::allocation_count();
        integrator->integrate(system, start, 1.0 + k);
        allocations[k] = *symdyn_test::allocation_count() - before;
        steps[k] = integrator->statistics().steps;
      }
      INFO(name << ", output interval " << interval << ": " << allocations[0] << " allocations in "
                << steps[0] << " steps, " << allocations[1] << " in " << steps[1]);
      CHECK(steps[1] > steps[0]);
      CHECK(allocations[1] == allocations[0]);
    }
  }
}
