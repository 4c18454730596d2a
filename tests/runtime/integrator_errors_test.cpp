// Each way a run stops, with the message checked.

#include <catch2/catch.hpp>

#include <regex>
#include <string>
#include <vector>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include "runtime/test_systems.hpp"

namespace {

using namespace symdyn::runtime;
using namespace symdyn::runtime::testing;

// The times "t = <number>" a message names.
std::vector<double> times_named(const std::string& message) {
  static const std::regex pattern(R"(t = ([-+0-9.eE]+))");
  std::vector<double> times;
  for (auto it = std::sregex_iterator(message.begin(), message.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    times.push_back(std::stod((*it)[1].str()));
  }
  return times;
}

// The message of the exception of type E that f throws ("" if none).
template <typename E, typename F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return {};
}

TEST_CASE("a NaN at t = 0.5 stops the run naming time and coordinate; earlier outputs kept",
          "[integrator][errors]") {
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    BreaksAtHalf sys;
    IntegratorOptions o;
    o.output_interval = 0.1;
    if (name == "rk4" || name == "midpoint") o.initial_step = 0.01;
    std::vector<double> delivered;
    o.on_output = [&](const State& s, const Vector&, const Vector&) { delivered.push_back(s.t); };
    auto integ = make_integrator(name, o);
    const std::string message =
        message_of<NumericError>([&] { integ->integrate(sys, initial_state(1.0, 0.0), 2.0); });
    INFO(message);
    CHECK(message.find("coordinate 'x'") != std::string::npos);
    CHECK(message.find("nan") != std::string::npos);
    const auto times = times_named(message);
    CHECK(std::any_of(times.begin(), times.end(), [](double t) { return t >= 0.5 && t < 0.6; }));
    // Every output instant before 0.5 was delivered, none after.
    REQUIRE(delivered.size() == 5);
    for (std::size_t k = 0; k < delivered.size(); ++k) {
      CHECK(delivered[k] == Approx(0.1 * static_cast<double>(k)).margin(1e-15));
    }
  }
}

TEST_CASE("step size underflow at a finite-time blow-up", "[integrator][errors]") {
  for (const char* name : {"newmark", "generalized-alpha", "dopri5", "cvode"}) {
    CAPTURE(name);
    BlowUp sys;
    IntegratorOptions o;
    o.min_step = 1e-10;
    auto integ = make_integrator(name, o);
    const std::string message =
        message_of<NumericError>([&] { integ->integrate(sys, initial_state(1.0, 1.0), 2.0); });
    INFO(message);
    REQUIRE(!message.empty());
    const auto times = times_named(message);
    REQUIRE(!times.empty());
    CHECK(times.front() > 0.99);  // at the blow-up (dopri5 may step just past it)
    CHECK(times.front() < 1.01);
    if (std::string(name) == "cvode") {
      CHECK(message.find("integrator 'cvode' failed with CV_") != std::string::npos);
    } else {
      CHECK(message.find("below min_step 1e-10") != std::string::npos);
    }
  }
}

TEST_CASE("unknown integrator name lists the valid ones", "[integrator][errors]") {
  const std::string message = message_of<OptionError>([] { make_integrator("euler"); });
  CHECK(message ==
        "unknown integrator 'euler'; valid names: newmark, generalized-alpha, rk4, dopri5, dop853, midpoint, cvode, arkode");
}

TEST_CASE("bad options are reported with the option named", "[integrator][errors]") {
  Oscillator osc;
  const State s0 = initial_state(1.0, 0.0);
  auto fails_with = [&](const std::string& name, IntegratorOptions o, double t_end) {
    return message_of<OptionError>([&] { make_integrator(name, o)->integrate(osc, s0, t_end); });
  };
  IntegratorOptions o;
  CHECK(fails_with("rk4", o, 1.0) ==
        "integrator 'rk4': a fixed-step run needs initial_step > 0 (the step)");
  o.relative_tolerance = -1.0;
  CHECK(fails_with("dopri5", o, 1.0) ==
        "integrator 'dopri5': tolerances must be positive (relative -1, absolute 1e-08)");
  o = {};
  o.output_times = {0.5, 2.0};
  CHECK(fails_with("newmark", o, 1.0) == "integrator 'newmark': output time 2 is outside [0, 1]");
  o = {};
  CHECK(fails_with("newmark", o, 0.0) ==
        "integrator 'newmark': the final time 0 must be finite and after the initial time 0");
  o.fixed_step = true;
  o.initial_step = 0.1;
  CHECK(fails_with("cvode", o, 1.0) ==
        "integrator 'cvode': fixed_step is not available (CVODE is adaptive)");
  o = {};
  o.rho_infinity = 1.5;
  CHECK(message_of<OptionError>([&] { make_integrator("generalized-alpha", o); }) ==
        "integrator 'generalized-alpha': rho_infinity 1.5 is outside [0, 1]");
}

TEST_CASE("a state of the wrong size is a ModelError", "[integrator][errors]") {
  FilteredOscillator sys(1.0, 0.1, 1.0);
  const std::string message = message_of<ModelError>(
      [&] { make_integrator("dopri5")->integrate(sys, initial_state(1.0, 0.0), 1.0); });
  CHECK(message ==
        "integrator 'dopri5': the initial state has q (1), qd (1), y (0); the system has 1 "
        "coordinates and 1 extra states");
}

TEST_CASE("a non-finite initial state is named", "[integrator][errors]") {
  Oscillator osc;
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    IntegratorOptions o;
    o.initial_step = 0.01;
    const std::string message = message_of<NumericError>(
        [&] { make_integrator(name, o)->integrate(osc, initial_state(1.0, INFINITY), 1.0); });
    INFO(message);
    CHECK(message.find("t = 0") == 0);
    CHECK(message.find("of coordinate 'x' is inf") != std::string::npos);
  }
}

TEST_CASE("q_scale of the wrong size or not positive names the option", "[integrator][errors]") {
  Oscillator osc;
  IntegratorOptions o;
  o.q_scale = {1.0, 2.0};
  CHECK_THROWS_WITH(make_integrator("dopri5", o)->integrate(osc, initial_state(1.0, 0.0), 1.0),
                    "integrator 'dopri5': q_scale has 2 entries, the system has 1 coordinates");
  o.q_scale = {0.0};
  CHECK_THROWS_WITH(make_integrator("cvode", o)->integrate(osc, initial_state(1.0, 0.0), 1.0),
                    "integrator 'cvode': q_scale[0] = 0 must be finite and positive");
}

}  // namespace

TEST_CASE("a solution that runs out of its model's domain stops every integrator, never creeps to the end",
          "[integrator][errors]") {
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    DomainEdge edge;
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = 1e-8;
    if (name == "rk4" || name == "midpoint") o.initial_step = 1e-3;
    double last_output = 0.0;
    o.output_interval = 0.01;
    o.on_output = [&](const State& s, const Vector&, const Vector&) { last_output = s.t; };
    auto integrator = make_integrator(name, o);
    const std::string m = message_of<NumericError>([&] { integrator->integrate(edge, initial_state(0.0, 1.0), 10.0); });
    CAPTURE(m);
    CHECK(m.find("crank") != std::string::npos);  // the non-finite value is named
    // q = 1 is reached near t = 0.8: the run stops there, with the outputs before it delivered.
    const std::vector<double> t = times_named(m);
    REQUIRE(!t.empty());
    CHECK(t.front() > 0.5);
    CHECK(t.front() < 1.0);
    CHECK(last_output > 0.5);
    CHECK(m.rfind("t = ", 0) == 0);
    static const std::regex repeated(R"(t = [-+0-9.eE]+: t = )");
    CHECK_FALSE(std::regex_search(m, repeated));  // one time prefix, not "t = 0.8: t = 0.8: ..."
  }
}

TEST_CASE("work is bounded: max_steps, and a fixed step below min_step or too many steps refused at once",
          "[integrator][errors]") {
  Oscillator osc;
  IntegratorOptions o;
  o.initial_step = 1e-300;
  CHECK_THROWS_WITH(make_integrator("rk4", o)->integrate(osc, initial_state(1.0, 0.0), 1.0),
                    "integrator 'rk4': initial_step 1e-300 is below min_step 1e-12");
  o.initial_step = 1e-9;
  CHECK_THROWS_WITH(make_integrator("rk4", o)->integrate(osc, initial_state(1.0, 0.0), 1.0),
                    "integrator 'rk4': a fixed step of 1e-09 s from t = 0 to 1 takes 1e+09 steps, over max_steps "
                    "100000000");
  IntegratorOptions adaptive;
  adaptive.max_steps = 50;
  adaptive.relative_tolerance = adaptive.absolute_tolerance = 1e-10;
  const std::string m = message_of<NumericError>(
      [&] { make_integrator("dopri5", adaptive)->integrate(osc, initial_state(1.0, 0.0), 100.0); });
  CHECK(m.find("50 step attempts reached max_steps (integrator 'dopri5')") != std::string::npos);
  // Output instants are computed as they come: 10^9 of them cost no memory up front.
  IntegratorOptions many;
  many.output_interval = 1e-9;
  std::size_t outputs = 0;
  many.on_output = [&](const State&, const Vector&, const Vector&) { ++outputs; };
  make_integrator("dopri5", many)->integrate(osc, initial_state(1.0, 0.0), 1e-6);
  CHECK(outputs == 1001);
}
