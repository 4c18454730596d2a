// global_tolerance is a promise: on the regular double pendulum, the slider-crank,
// robot3d and the trike, every integrator at global tolerance 1e-6 (fixed-step ones
// by step halving, adaptive ones by tightening) returns a result within it, with an
// estimate within a factor 10 of its error both ways against a tight reference (dop853
// at 1e-13, confirmed by dopri5 at 1e-12), and a run that returns has met it. A few
// seconds of motion each.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <functional>
#include <numbers>
#include <string>
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
                    "tolerance {:g})",
                    model, s.integrator, s.fixed_step ? " (fixed_step)" : "", error, estimate,
                    r.stats.runs, r.stats.last_step, r.stats.last_relative_tolerance));
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
