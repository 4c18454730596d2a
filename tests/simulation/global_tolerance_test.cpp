// global_tolerance is a promise: on the regular double pendulum, the slider-crank,
// robot3d and the trike, every integrator at global tolerance 1e-6 (fixed-step ones
// by step halving, adaptive ones by tightening) returns a result within it, with an
// estimate within a factor 10 of its error both ways against a tight reference (dop853
// at 1e-13, confirmed by dopri5 at 1e-12), and a run that returns has met it. A few
// seconds of motion each.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "double_pendulum_absolute.hpp"
#include "robot3d_absolute.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include "slider_crank_dependent.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;

constexpr double kGlobal = 1e-6;
// Below it the reference (uncertain by ~1e-10) cannot judge an error, nor the factor 10.
constexpr double kFloor = 1e-9;

struct Setting {
  std::string integrator;
  double step = 0.0;  // > 0: fixed steps from it (rk4, midpoint, fixed_step)
  bool fixed_step = false;
};

// The settings every model is run with: the adaptive methods from a local
// tolerance of 1e-6, the fixed-step ones from a step of `h`.
std::vector<Setting> settings(double h, bool implicit_fixed) {
  std::vector<Setting> s = {{"rk4", h},  {"midpoint", h},       {"dopri5"}, {"dop853"},
                            {"newmark"}, {"generalized-alpha"}, {"cvode"},  {"arkode"}};
  if (implicit_fixed) {
    s.push_back({"newmark", h, true});
    s.push_back({"generalized-alpha", h, true});
    s.push_back({"dopri5", 4 * h, true});
  }
  return s;
}

struct Outcome {
  State end;
  Statistics stats;
};

using Solver = std::function<Outcome(const Setting& s, double tolerance, double global)>;

double max_error(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

void check_promise(const std::string& model, const Solver& solve, const std::vector<Setting>& all) {
  const State reference = solve({"dop853"}, 1e-13, 0.0).end;
  const double uncertainty = max_error(reference, solve({"dopri5"}, 1e-12, 0.0).end);
  INFO(fmt::format("{}: the reference is confirmed to {:.2g}", model, uncertainty));
  REQUIRE(uncertainty < 1e-3 * kGlobal);
  for (const Setting& s : all) {
    Outcome r;
    try {
      r = solve(s, 1e-6, kGlobal);
    } catch (const NumericError& e) {
      FAIL(fmt::format("{}, {}{}: {}", model, s.integrator, s.fixed_step ? " (fixed_step)" : "",
                       e.what()));
    }
    const double error = max_error(r.end, reference);
    const double estimate = r.stats.global_error_estimate;
    INFO(
        fmt::format("{}, {}{}: error {:.3g}, estimate {:.3g} in {} runs (the last at step {:g}, "
                    "tolerance {:g}){}",
                    model, s.integrator, s.fixed_step ? " (fixed_step)" : "", error, estimate,
                    r.stats.runs, r.stats.last_step, r.stats.last_relative_tolerance,
                    r.stats.extrapolated ? ", extrapolated" : ""));
    CHECK(r.stats.global_tolerance_met);
    CHECK(estimate <= kGlobal);
    CHECK(error <= kGlobal);
    CHECK(std::max(estimate, kFloor) <= 10.0 * std::max(error, kFloor));
    CHECK(std::max(error, kFloor) <= 10.0 * std::max(estimate, kFloor));
  }
}

Solver system_solver(MultibodySystem& system, const State& initial, double t_end) {
  return [&system, initial, t_end](const Setting& s, double tolerance, double global) {
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = tolerance;
    o.global_tolerance = global;
    o.initial_step = s.step;
    o.fixed_step = s.fixed_step;
    o.output_times = {t_end};
    auto integ = make_integrator(s.integrator, o);
    Outcome r{integ->integrate(system, initial, t_end), {}};
    r.stats = integ->statistics();
    return r;
  };
}

}  // namespace

TEST_CASE(
    "global tolerance, double pendulum (regular swing, 2 s): every integrator's estimate and "
    "result",
    "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::double_pendulum_absolute>(),
                      EquationsSource::emitted);
  State x0 = sys.initial_state();
  x0.q << -std::numbers::pi / 2 + 0.5, 0.5;
  x0.qd.setZero();
  check_promise("double pendulum", system_solver(sys, x0, 2.0), settings(0.02, true));
}

TEST_CASE("global tolerance, slider-crank (5 rad/s, 2 s): every integrator's estimate and result",
          "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::slider_crank_dependent>(),
                      EquationsSource::emitted);
  State x0 = sys.initial_state();
  x0.q.setZero();
  x0.qd.setConstant(5.0);
  check_promise("slider-crank", system_solver(sys, x0, 2.0), settings(0.02, true));
}

TEST_CASE("global tolerance, robot3d (1 s): every integrator's estimate and result",
          "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::robot3d_absolute>(), EquationsSource::emitted);
  State x0 = sys.initial_state();
  x0.qd.setConstant(1.0);
  check_promise("robot3d", system_solver(sys, x0, 1.0), settings(0.02, false));
}

TEST_CASE("global tolerance, trike scenario (1 s): every integrator's estimate and result",
          "[models][global]") {
  const Solver solve = [](const Setting& s, double tolerance, double global) {
    symdyn::sim::RunOptions o;
    o.t_end = 1.0;
    o.integrator = s.integrator;
    o.output_interval = 1.0;
    o.tolerance = tolerance;
    if (s.step > 0.0) o.step = s.step;
    if (global > 0.0) o.global_tolerance = global;
    symdyn::sim::Simulation sim(symdyn::sim::find_builtin("trike"), o);
    const symdyn::sim::RunResult r = sim.run();
    return Outcome{r.final, r.statistics};
  };
  check_promise("trike", solve, settings(0.001, false));
}

// A fixed step of unknown order cannot be halved with a known estimate: refused.
TEST_CASE("global tolerance with arkode at a fixed step is refused before the run",
          "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::double_pendulum_absolute>(),
                      EquationsSource::emitted);
  IntegratorOptions o;
  o.global_tolerance = 1e-6;
  o.fixed_step = true;
  o.initial_step = 0.01;
  CHECK_THROWS_WITH(make_integrator("arkode", o)->integrate(sys, sys.initial_state(), 1.0),
                    "integrator 'arkode': global_tolerance at a fixed step needs the method's "
                    "order, which 'arkode' "
                    "does not give: drop fixed_step or global_tolerance");
}

// Step halving returns (2^p·x_h - x_2h)/(2^p - 1) of its last two runs where they are in
// the asymptotic range: of order p + 2 for a symmetric method (newmark's trapezoidal rule),
// p + 1 otherwise (rk4), at the end and at every output, with the error estimated from the
// extrapolations of runs 1-2, 2-3 and 3-4. Checked against runs made apart and combined
// here, against the reference, and by the order the extrapolated error falls with.
TEST_CASE("step halving returns the Richardson extrapolation of its last two runs",
          "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::double_pendulum_absolute>(),
                      EquationsSource::emitted);
  const State x0 = sys.initial_state();  // released horizontal (the work-precision problem)
  constexpr double kEnd = 1.0;
  IntegratorOptions tight;
  tight.relative_tolerance = tight.absolute_tolerance = 1e-13;
  tight.output_times = {kEnd};
  const State reference = make_integrator("dop853", tight)->integrate(sys, x0, kEnd);
  tight.relative_tolerance = tight.absolute_tolerance = 1e-12;
  REQUIRE(max_error(reference, make_integrator("dopri5", tight)->integrate(sys, x0, kEnd)) < 1e-10);

  struct Case {
    const char* integrator;
    int gained;     // orders the extrapolation gains
    double global;  // met by the extrapolation of steps 2e-3 and 1e-3, not by a run alone
  };
  for (const Case c : {Case{"newmark", 2, 1e-6}, Case{"rk4", 1, 1e-9}}) {
    const int p = c.integrator == std::string("rk4") ? 4 : 2;
    // One run of fixed step h, Newton solved to rounding as step halving does; outputs kept.
    const auto fixed_run = [&](double h, std::vector<State>* outputs) {
      IntegratorOptions o;
      o.fixed_step = true;
      o.initial_step = h;
      o.relative_tolerance = o.absolute_tolerance = 1e-13;
      o.output_interval = 0.2;  // on every run's steps
      if (outputs)
        o.on_output = [outputs](const State& s, const Vector&, const Vector&) {
          outputs->push_back(s);
        };
      return make_integrator(c.integrator, o)->integrate(sys, x0, kEnd);
    };
    const auto halving_run = [&](double h0, double global, std::vector<State>* outputs) {
      IntegratorOptions o;
      o.fixed_step = true;
      o.initial_step = h0;
      o.global_tolerance = global;
      o.output_interval = 0.2;  // on every run's steps
      if (outputs)
        o.on_output = [outputs](const State& s, const Vector&, const Vector&) {
          outputs->push_back(s);
        };
      auto integ = make_integrator(c.integrator, o);
      const State end = integ->integrate(sys, x0, kEnd);
      return std::pair{end, integ->statistics()};
    };
    INFO(c.integrator);
    std::vector<State> outputs, coarse_outputs, fine_outputs;
    const auto [end, stats] = halving_run(8e-3, c.global, &outputs);
    CHECK(stats.global_tolerance_met);
    CHECK(stats.extrapolated);
    CHECK(stats.runs == 4);
    CHECK(stats.last_step == 1e-3);
    const State coarser = fixed_run(4e-3, nullptr), coarse = fixed_run(2e-3, &coarse_outputs),
                fine = fixed_run(1e-3, &fine_outputs);
    const double c_p = 1.0 / (std::pow(2.0, p) - 1.0);
    const auto combined = [&](const State& a, const State& b) {
      return State{b.t, b.q + c_p * (b.q - a.q), b.qd + c_p * (b.qd - a.qd), b.y};
    };
    CHECK(max_error(end, combined(coarse, fine)) < 1e-13);
    REQUIRE(outputs.size() == 6);  // t = 0 to 1
    REQUIRE(fine_outputs.size() == 6);
    for (std::size_t k = 0; k < outputs.size(); ++k) {
      CHECK(outputs[k].t == fine_outputs[k].t);
      CHECK(max_error(outputs[k], combined(coarse_outputs[k], fine_outputs[k])) < 1e-13);
    }
    const double error = max_error(end, reference);
    INFO(fmt::format("error {:.3g}, estimate {:.3g}", error, stats.global_error_estimate));
    CHECK(error <= stats.global_error_estimate * 10.0);
    CHECK(stats.global_error_estimate <= error * 10.0);

    // Extrapolated from steps of 2e-3 and 1e-3 against 4e-3 and 2e-3: the error falls as
    // h^(p + gained).
    const double coarser_error = max_error(combined(coarser, coarse), reference);
    const double order = std::log2(coarser_error / error);
    INFO(fmt::format("extrapolated errors {:.3g} and {:.3g}: order {:.2f}", coarser_error, error,
                     order));
    CHECK(std::abs(order - (p + c.gained)) < 0.5);
  }
}

// Rounding grows with the steps: a tolerance below what a run's steps may round to is
// refused as soon as the runs get there, naming it.
TEST_CASE("step halving stops where the runs' rounding is above the global tolerance",
          "[models][global]") {
  MultibodySystem sys(Model::from<symdyn_generated::double_pendulum_absolute>(),
                      EquationsSource::emitted);
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = 1e-2;
  o.global_tolerance = 1e-14;
  CHECK_THROWS_WITH(
      make_integrator("newmark", o)->integrate(sys, sys.initial_state(), 1.0),
      Catch::Matchers::StartsWith(
          "integrator 'newmark': global_tolerance 1e-14 not reached by step halving "
          "from initial_step 0.01 (the rounding of its 400 steps, up to ") &&
          Catch::Matchers::Contains("is above it): the result at a step of 0.0025 s"));
}
