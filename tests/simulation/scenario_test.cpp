// The built-in scenarios of symdyn-sim (models/scenarios/*.json): every one
// runs with its defaults and its checks fall in their bands; the double
// pendulum's and the slider-crank's runs are also checked against closed forms.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "run.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn;
using Catch::Matchers::Contains;

constexpr double two_pi = 2.0 * std::numbers::pi;

// Every output instant of a run, through the sample callback.
std::vector<runtime::State> states_of(const sim::Scenario& s, sim::RunOptions o = {}) {
  std::vector<runtime::State> states;
  o.on_sample = [&](const runtime::State& st, const runtime::Vector&) { states.push_back(st); };
  sim::run_scenario(s, o);
  return states;
}

// The crank's speed where its angle passes target (mod 2 pi), from the parabola
// through the three samples around each passage (increasing; samples 0.05 rad apart).
std::vector<double> speeds_at(const std::vector<runtime::State>& samples, double target) {
  std::vector<double> out;
  for (std::size_t k = 1; k + 1 < samples.size(); ++k) {
    const auto& a = samples[k - 1];
    const auto& b = samples[k];
    const auto& c = samples[k + 1];
    const double ub = std::floor((b.q(0) - target) / two_pi),
                 uc = std::floor((c.q(0) - target) / two_pi);
    if (ub == uc) continue;
    const double x = target + uc * two_pi;
    const double xa = a.q(0), xb = b.q(0), xc = c.q(0);
    out.push_back(a.qd(0) * (x - xb) * (x - xc) / ((xa - xb) * (xa - xc)) +
                  b.qd(0) * (x - xa) * (x - xc) / ((xb - xa) * (xb - xc)) +
                  c.qd(0) * (x - xa) * (x - xb) / ((xc - xa) * (xc - xb)));
  }
  return out;
}

}  // namespace

TEST_CASE("every built-in scenario runs with its defaults and its checks are in their bands",
          "[models][scenario]") {
  REQUIRE(sim::builtin_scenarios().size() >= 4);
  for (const sim::Scenario& s : sim::builtin_scenarios()) {
    CAPTURE(s.name);
    const sim::RunResult r = sim::run_scenario(s);
    CHECK(r.final.t == s.t_end);
    CHECK(r.rows == std::lround(s.t_end / s.output_interval) + 1);
    CHECK(r.statistics.steps > 0);
    REQUIRE_FALSE(r.checks.empty());
    for (const auto& c : r.checks) {
      INFO(c.name << " = " << c.value << " " << c.unit << ", expected " << c.low << " .. "
                  << c.high);
      CHECK(c.ok());
    }
  }
}

TEST_CASE("a scenario's coordinate springs and actuators keep their exact derivatives",
          "[models][scenario]") {
  // The trike's drive (an expression of chassis.ux) and its tyres: all exact.
  sim::Simulation sim(sim::find_builtin("trike"));
  runtime::MultibodySystem& system = sim.system();
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  runtime::State s = system.initial_state();
  s.t = 1.1;  // steering
  s.q(10) = 0.05;
  s.qd(10) = 0.3;
  // The wheels 1 cm into the ground: at the initial height they just touch it, where the
  // tyres' law switches and differences straddle the switch.
  s.q(2) -= 0.01;
  runtime::Vector qdd, yd;
  system.accelerations(s, qdd, yd);
  runtime::Matrix M, C, K, Md, Cd, Kd;
  system.jacobians(s, qdd, M, C, K);
  system.set_exact_jacobians(false);
  system.jacobians(s, qdd, Md, Cd, Kd);
  const double scale = std::max({1.0, Kd.cwiseAbs().maxCoeff(), Cd.cwiseAbs().maxCoeff()});
  CHECK((K - Kd).cwiseAbs().maxCoeff() < 1e-6 * scale);
  CHECK((C - Cd).cwiseAbs().maxCoeff() < 1e-6 * scale);
}

TEST_CASE("double pendulum scenario: CSV columns, rows, and the tip from the coordinates",
          "[models][scenario]") {
  std::ostringstream csv;
  sim::RunOptions o;
  o.csv = &csv;
  o.t_end = 2.0;
  const sim::RunResult r = sim::run_scenario(sim::find_builtin("double_pendulum"), o);
  CHECK(r.columns == std::vector<std::string>{"t", "theta1", "theta2", "theta1_dot", "theta2_dot",
                                              "kinetic_energy", "gravitational_energy",
                                              "elastic_energy", "total_energy", "tip_x", "tip_y"});
  REQUIRE(r.rows == 201);
  std::istringstream in(csv.str());
  std::string line, last;
  int lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    last = line;
  }
  CHECK(lines == 202);  // header and 201 instants
  // The tip of rod 2: (cos theta1 + cos(theta1 + theta2), sin theta1 + sin(theta1 + theta2)) for l1
  // = l2 = 1.
  const auto& q = r.final.q;
  std::vector<double> values;
  std::istringstream fields(last);
  for (std::string f; std::getline(fields, f, ',');) values.push_back(std::stod(f));
  REQUIRE(values.size() == 11);
  CHECK(values[0] == 2.0);
  CHECK(values[9] == Approx(std::cos(q(0)) + std::cos(q(0) + q(1))).margin(1e-12));
  CHECK(values[10] == Approx(std::sin(q(0)) + std::sin(q(0) + q(1))).margin(1e-12));
  CHECK(sim::summary(r).find("energy: initial 0 J") != std::string::npos);
}

TEST_CASE("slider-crank scenario: crank speed where energy conservation gives it in closed form",
          "[models][scenario]") {
  // E = 1/2 M(crank) crank_dot^2 + V(crank) with, by hand (l1 = 0.1, l2 = 0.3, models.md):
  //   crank = 0 (dead centre, alpha = 0, alpha' = crank_dot / 3, slider at rest):
  //     M = (8.333e-4 + 1 * 0.05^2) + 0.5 * 0.05^2 + 3.75e-3 / 9 = 5e-3, V = 0
  //   crank = pi/2 and 3 pi/2 (alpha' = 0, rod and slider translate at l1 crank_dot):
  //     M = 3.333e-3 + (0.5 + 0.3) * 0.1^2 = 1.1333e-2,
  //     V = +-9.81 (1 * 0.05 + 0.5 * 0.05) = +-0.73575 J
  const double M0 = 8.3333333333333333e-4 + 0.0025 + 0.5 * 0.0025 + 3.75e-3 / 9.0;
  const double M90 = 8.3333333333333333e-4 + 0.0025 + 0.8 * 0.01;
  const double E = 0.5 * M0 * 50.0 * 50.0, V90 = 9.81 * 0.075;
  const double at_90 = std::sqrt(2.0 * (E - V90) / M90), at_270 = std::sqrt(2.0 * (E + V90) / M90);
  const sim::Scenario& s = sim::find_builtin("slider_crank");
  std::vector<std::vector<runtime::State>> runs;
  for (const char* variant : {"inline", "dependent"}) {
    sim::RunOptions o;
    o.variant = variant;
    runs.push_back(states_of(s, o));
    const auto& r = runs.back();
    CAPTURE(variant);
    const auto w0 = speeds_at(r, 0.0), w90 = speeds_at(r, std::numbers::pi / 2),
               w270 = speeds_at(r, 1.5 * std::numbers::pi);
    REQUIRE(w0.size() >= 5);
    REQUIRE(w90.size() >= 5);
    REQUIRE(w270.size() >= 5);
    for (double w : w0) CHECK(w == Approx(50.0).epsilon(1e-4));
    for (double w : w90) CHECK(w == Approx(at_90).epsilon(1e-4));
    for (double w : w270) CHECK(w == Approx(at_270).epsilon(1e-4));
  }
  // Inline and dependent variants: the same motion.
  REQUIRE(runs.size() == 2);
  REQUIRE(runs[0].size() == runs[1].size());
  for (std::size_t k = 0; k < runs[0].size(); ++k)
    CHECK(std::abs(runs[0][k].q(0) - runs[1][k].q(0)) < 1e-7);
}

TEST_CASE("scenario errors name the culprit", "[models][scenario]") {
  CHECK_THROWS_WITH(sim::find_builtin("pendulum"),
                    Contains("no scenario for model 'pendulum'") && Contains("double_pendulum"));
  sim::RunOptions inline_variant;
  inline_variant.variant = "inline";
  CHECK_THROWS_WITH(sim::Simulation(sim::find_builtin("double_pendulum"), inline_variant),
                    Contains("no variant 'inline'") && Contains("absolute, relative"));
  sim::RunOptions o;
  o.integrator = "euler";
  CHECK_THROWS_AS(sim::run_scenario(sim::find_builtin("double_pendulum"), o), runtime::OptionError);
}

// The output interval never changes a result: rk4 and midpoint take the step given
// (none from the interval), the others interpolate between their own steps.
TEST_CASE(
    "slider-crank scenario: two output intervals give bit-identical final states with every "
    "integrator",
    "[models][scenario]") {
  for (const auto& name : runtime::integrator_names()) {
    CAPTURE(name);
    const auto final_state = [&](double interval) {
      sim::RunOptions o;
      o.t_end = 2.0;
      o.integrator = name;
      o.tolerance = 1e-6;
      o.output_interval = interval;
      if (name == "rk4" || name == "midpoint") o.step = 1e-3;
      return sim::run_scenario(sim::find_builtin("slider_crank"), o).final;
    };
    const runtime::State a = final_state(0.01), b = final_state(0.001);
    CHECK(a.t == b.t);
    CHECK(a.q == b.q);  // bit for bit
    CHECK(a.qd == b.qd);
  }
}

TEST_CASE("rk4 and midpoint in a scenario need a step, and the message says where to give it",
          "[models][scenario]") {
  for (const char* name : {"rk4", "midpoint"}) {
    sim::RunOptions o;
    o.integrator = name;
    CHECK_THROWS_WITH(
        sim::Simulation(sim::find_builtin("double_pendulum"), o),
        fmt::format(
            "integrator '{}' takes a fixed step: give one (--step, or the scenario's integrator "
            "\"step\")",
            name));
  }
}

TEST_CASE("the run summary says whether the global error was estimated and met",
          "[models][scenario]") {
  sim::RunOptions o;
  o.t_end = 1.0;
  o.integrator = "rk4";
  o.step = 0.01;
  const std::string plain = sim::summary(sim::run_scenario(sim::find_builtin("slider_crank"), o));
  CHECK_THAT(plain, Contains("global error: not estimated"));
  o.global_tolerance = 1e-6;
  const sim::RunResult r = sim::run_scenario(sim::find_builtin("slider_crank"), o);
  CHECK(r.statistics.global_tolerance_met);
  CHECK(r.statistics.global_error_estimate <= 1e-6);
  CHECK_THAT(sim::summary(r), Contains("global tolerance 1e-06 met"));
}

TEST_CASE("a scenario outputs and checks joint reactions by name", "[models][scenario]") {
  // Hanging straight down at rest, every rod from the ground: rod 2's pin
  // holds its weight, up, which is -x in its axes (docs/emitted_interface.md).
  const sim::Scenario s = sim::parse_scenario(R"json({
    "model": "double_pendulum",
    "initial": {"q": {"theta1": -1.5707963267948966, "theta2": 0}},
    "t_end": 0.1,
    "output_interval": 0.05,
    "outputs": [{"body": "rod2", "quantity": "reaction"}],
    "checks": [{"name": "rod 2's pin", "value": "maximum(abs(reaction.rod2.Fx + 9.81))",
                "band": [0, 1e-9]}]
  })json",
                                              "reactions.json");
  std::ostringstream csv;
  sim::RunOptions o;
  o.csv = &csv;
  const sim::RunResult r = sim::run_scenario(s, o);
  CHECK(r.columns == std::vector<std::string>{"t", "reaction.rod2.Fx", "reaction.rod2.Fy",
                                              "reaction.rod2.Fz", "reaction.rod2.Mx",
                                              "reaction.rod2.My", "reaction.rod2.Mz"});
  REQUIRE(r.checks.size() == 1);
  CHECK(r.checks[0].ok());
  // A model generated without them says so, and how to generate them.
  const sim::Scenario trike = sim::parse_scenario(
      R"json({"model": "trike", "t_end": 0.1,
              "outputs": [{"name": "f", "value": "reaction.chassis.Fx"}]})json",
      "trike.json");
  CHECK_THROWS_WITH(sim::Simulation(trike), Contains("without joint reactions"));
}
