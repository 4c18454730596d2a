// Integrators against closed-form solutions.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "runtime/test_systems.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn::runtime;
using namespace symdyn::runtime::testing;

// Options for a tight-tolerance run with outputs every `interval`.
IntegratorOptions tight(const std::string& name, double tol, double interval) {
  IntegratorOptions o;
  o.relative_tolerance = tol;
  o.absolute_tolerance = tol;
  o.output_interval = interval;
  if (name == "rk4") o.initial_step = 1e-3;
  if (name == "midpoint") o.initial_step = 1e-4;
  return o;
}

struct Sample {
  State s;
  Vector qdd, yd;
};

// Runs and returns every delivered output.
std::vector<Sample> run(const std::string& name, IntegratorOptions o, DynamicSystem& sys,
                        const State& s0, double t_end, Statistics* stats = nullptr) {
  std::vector<Sample> out;
  o.on_output = [&](const State& s, const Vector& qdd, const Vector& yd) {
    out.push_back({s, qdd, yd});
  };
  auto integ = make_integrator(name, o);
  integ->integrate(sys, s0, t_end);
  if (stats != nullptr) *stats = integ->statistics();
  return out;
}

TEST_CASE("every integrator follows q = cos 2 pi t at tight tolerance", "[integrator]") {
  Oscillator osc;
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    // The second-order methods, and arkode (an L-stable method whose damping of the
    // oscillation adds up), reach a lesser accuracy at the same tolerance.
    const bool looser =
        name == "newmark" || name == "generalized-alpha" || name == "arkode" || name == "midpoint";
    IntegratorOptions o = tight(name, 1e-10, 0.05);
    Statistics stats;
    const auto out = run(name, o, osc, initial_state(1.0, 0.0), 2.0, &stats);
    REQUIRE(out.size() == 41);
    double worst = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double t = out[k].s.t;
      REQUIRE(t == 0.05 * static_cast<double>(k));  // output instants hit exactly
      worst = std::max(
          {worst, std::abs(out[k].s.q[0] - std::cos(two_pi * t)),
           std::abs(out[k].s.qd[0] + two_pi * std::sin(two_pi * t)) / two_pi,
           std::abs(out[k].qdd[0] + two_pi * two_pi * std::cos(two_pi * t)) / (two_pi * two_pi)});
    }
    CHECK(worst < (looser ? 2e-6 : 1e-7));
    CHECK(stats.steps > 0);
  }
}

TEST_CASE("EasyDyn's spring along an arbitrary direction gives q = 1 + (q0 - 1) cos 2 pi t",
          "[integrator]") {
  const Eigen::Vector3d directions[] = {{1, 0, 0}, {0.3, -0.5, 0.8}, {-2, 1, 7}};
  for (const auto& u : directions) {
    SpringAlongDirection spring(u);
    for (const auto& name : integrator_names()) {
      CAPTURE(name, u.transpose());
      const auto out = run(name, tight(name, 1e-10, 0.1), spring, initial_state(1.5, 0.0), 1.0);
      for (const auto& o : out) {
        CHECK(std::abs(o.s.q[0] - (1.0 + 0.5 * std::cos(two_pi * o.s.t))) < 2e-6);
      }
    }
  }
}

// Largest |q - cos 2 pi t| over the outputs of a fixed-step run of step h on [0, 1].
double fixed_step_error(const std::string& name, double h) {
  Oscillator osc;
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = h;
  o.output_interval = 0.25;
  o.relative_tolerance = 1e-13;  // Newton converged far below the truncation error
  o.absolute_tolerance = 1e-13;
  double worst = 0.0;
  for (const auto& s : run(name, o, osc, initial_state(1.0, 0.0), 1.0)) {
    worst = std::max(worst, std::abs(s.s.q[0] - std::cos(two_pi * s.s.t)));
  }
  return worst;
}

TEST_CASE("observed order of accuracy when halving a fixed step", "[integrator][order]") {
  struct Case {
    const char* name;
    double order;
    double h;
  };
  const Case cases[] = {
      {"rk4", 4, 1.0 / 40},    {"newmark", 2, 1.0 / 80}, {"generalized-alpha", 2, 1.0 / 80},
      {"dopri5", 5, 1.0 / 20}, {"dop853", 8, 1.0 / 8},   {"midpoint", 2, 1.0 / 80},
      {"arkode", 4, 1.0 / 40}};
  for (const auto& c : cases) {
    const double e1 = fixed_step_error(c.name, c.h);
    const double e2 = fixed_step_error(c.name, c.h / 2);
    const double e3 = fixed_step_error(c.name, c.h / 4);
    INFO(fmt::format("{}: errors {:.3e} {:.3e} {:.3e}, orders {:.3f} {:.3f}", c.name, e1, e2, e3,
                     std::log2(e1 / e2), std::log2(e2 / e3)));
    CHECK(std::abs(std::log2(e1 / e2) - c.order) < 0.3);
    CHECK(std::abs(std::log2(e2 / e3) - c.order) < 0.3);
  }
}

TEST_CASE("dopri5's error scales like its tolerance", "[integrator][order]") {
  Oscillator osc;
  auto error = [&](double tol) {
    double worst = 0.0;
    for (const auto& s :
         run("dopri5", tight("dopri5", tol, 0.1), osc, initial_state(1.0, 0.0), 2.0)) {
      worst = std::max(worst, std::abs(s.s.q[0] - std::cos(two_pi * s.s.t)));
    }
    return worst;
  };
  // Proportional in the mean: a factor 100 in tolerance gives a factor ~100 in error.
  const double e6 = error(1e-6), e8 = error(1e-8), e10 = error(1e-10);
  INFO(fmt::format("errors {:.3e} {:.3e} {:.3e}", e6, e8, e10));
  CHECK(std::log10(e6 / e8) > 1.5);
  CHECK(std::log10(e6 / e8) < 2.5);
  CHECK(std::log10(e8 / e10) > 1.5);
  CHECK(std::log10(e8 / e10) < 2.5);
}

TEST_CASE("damped oscillator driving a low-pass filter (extra first-order state)",
          "[integrator][extra]") {
  const double w = two_pi, zeta = 0.1, tau = 0.2;
  FilteredOscillator sys(w, zeta, tau);
  const double q0 = 1.0, v0 = 0.5, y0 = -0.3;
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    const bool looser =
        name == "newmark" || name == "generalized-alpha" || name == "arkode" || name == "midpoint";
    Statistics stats;
    const auto out =
        run(name, tight(name, 1e-10, 0.1), sys, initial_state(q0, v0, y0), 3.0, &stats);
    REQUIRE(out.size() == 31);
    double worst_q = 0.0, worst_y = 0.0, worst_yd = 0.0;
    for (const auto& o : out) {
      const double t = o.s.t;
      const double y = sys.exact_filter(t, q0, v0, y0);
      worst_q = std::max(worst_q, std::abs(o.s.q[0] - sys.exact(t, q0, v0)));
      worst_y = std::max(worst_y, std::abs(o.s.y[0] - y));
      worst_yd = std::max(worst_yd, std::abs(o.yd[0] - (sys.exact(t, q0, v0) - y) / tau));
    }
    INFO(fmt::format("errors q {:.2e} y {:.2e} yd {:.2e}, {} steps", worst_q, worst_y, worst_yd,
                     stats.steps));
    CHECK(worst_q < (looser ? 5e-6 : 1e-7));
    CHECK(worst_y < (looser ? 5e-6 : 1e-7));
    CHECK(worst_yd < (looser ? 2e-5 : 1e-6));
  }
}

TEST_CASE("nonlinear pendulum conserves energy to 1e-9 with dopri5 and cvode", "[integrator]") {
  Pendulum p;
  const State s0 = initial_state(1.0, 0.0);
  const double e0 = p.energy(s0);
  for (const char* name : {"dopri5", "cvode"}) {
    CAPTURE(name);
    double worst = 0.0;
    // BDF is dissipative: CVODE needs a tighter tolerance for the same drift.
    const double tol = std::string(name) == "cvode" ? 1e-13 : 1e-12;
    for (const auto& o : run(name, tight(name, tol, 0.01), p, s0, 10.0)) {
      worst = std::max(worst, std::abs(p.energy(o.s) - e0) / std::abs(e0));
    }
    INFO(fmt::format("largest relative energy drift {:.3e}", worst));
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("stiff spring-damper chain: implicit methods take few steps", "[integrator][stiff]") {
  // Stiff mode: w ~ 1.4e4 rad/s, damping ratio ~ 0.7; soft mode 1 Hz.
  StiffChain chain(1e8, 1e4);
  Eigen::Vector2d q0(1.0, 1.0), v0(0.0, 0.0);
  State s0;
  s0.q = q0;
  s0.qd = v0;
  for (const char* name : {"newmark", "generalized-alpha", "cvode", "dopri5"}) {
    CAPTURE(name);
    // newmark and generalized-alpha at 1e-4: their error at t_end falls in proportion to
    // the tolerance (about 3e-4 here); cvode and dopri5 bound each step's error by 1e-6.
    const bool second_order =
        std::string(name) == "newmark" || std::string(name) == "generalized-alpha";
    IntegratorOptions o = tight(name, second_order ? 1e-4 : 1e-6, 0.1);
    Statistics stats;
    const auto out = run(name, o, chain, s0, 5.0, &stats);
    double worst = 0.0;
    for (const auto& s : out) {
      worst = std::max(worst, (s.s.q - Vector(chain.exact(s.s.t, q0, v0))).cwiseAbs().maxCoeff());
    }
    INFO(fmt::format("{}: {} steps, {} rejected, {} rhs, {} residual, {} Jacobians, error {:.2e}",
                     name, stats.steps, stats.rejected_steps, stats.rhs_evaluations,
                     stats.residual_evaluations, stats.jacobian_evaluations, worst));
    CHECK(worst < 3e-3);
    if (std::string(name) != "dopri5") CHECK(stats.steps < 3000);
  }
}

TEST_CASE("newmark keeps its Jacobian across steps on a linear system", "[integrator]") {
  StiffChain chain(1e4, 1.0);
  State s0;
  s0.q = Eigen::Vector2d(1.0, 1.0);
  s0.qd = Eigen::Vector2d(0.0, 0.0);
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = 1e-3;
  auto integ = make_integrator("newmark", o);
  integ->integrate(chain, s0, 1.0);
  const auto& st = integ->statistics();
  CHECK(st.steps == 1000);
  CHECK(st.jacobian_evaluations == 1);                // exact Jacobian never slows Newton
  CHECK(st.newton_iterations <= 2 * (st.steps + 1));  // linear: one correction, one check
  CHECK(st.residual_evaluations == st.newton_iterations);
}

TEST_CASE("newmark refreshes its kept Jacobian when the stiffness changes", "[integrator]") {
  ConfigurationStiff sys(1e8, 1e4);
  State s0;
  s0.q = Eigen::Vector2d(1.0, 1.0);
  s0.qd = Eigen::Vector2d(0.0, 0.0);
  const auto reference = run("cvode", tight("cvode", 1e-11, 0.05), sys, s0, 2.0);
  for (const char* name : {"newmark", "generalized-alpha"}) {
    CAPTURE(name);
    Statistics stats;
    const auto out = run(name, tight(name, 1e-6, 0.05), sys, s0, 2.0, &stats);
    REQUIRE(out.size() == reference.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      worst = std::max(worst, (out[k].s.q - reference[k].s.q).cwiseAbs().maxCoeff());
    }
    INFO(fmt::format("error {:.2e}; {} steps, {} Jacobians, {} Newton iterations", worst,
                     stats.steps, stats.jacobian_evaluations, stats.newton_iterations));
    CHECK(worst < 1e-3);
    CHECK(stats.jacobian_evaluations > 1);            // refreshed when convergence slowed
    CHECK(stats.jacobian_evaluations < stats.steps);  // and kept across steps otherwise
  }
}

TEST_CASE("outputs at a list of times, and at every step", "[integrator][output]") {
  Oscillator osc;
  const std::vector<double> times = {0.0, 0.013, 0.5, 0.77, 1.2};
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    IntegratorOptions o = tight(name, 1e-9, 0.0);
    o.output_times = times;
    std::vector<double> seen, progress;
    o.on_progress = [&](double t, double t0, double t1) {
      CHECK(t0 == 0.0);
      CHECK(t1 == 1.5);
      progress.push_back(t);
    };
    for (const auto& s : run(name, o, osc, initial_state(1.0, 0.0), 1.5)) {
      seen.push_back(s.s.t);
      CHECK(std::abs(s.s.q[0] - std::cos(two_pi * s.s.t)) < 1e-5);
    }
    std::vector<double> expected = times;
    expected.push_back(1.5);
    CHECK(seen == expected);
    REQUIRE(!progress.empty());
    CHECK(std::is_sorted(progress.begin(), progress.end()));
    CHECK(progress.back() == 1.5);

    // No schedule: every accepted step, ending at t_end.
    IntegratorOptions every = tight(name, 1e-6, 0.0);
    Statistics stats;
    const auto all = run(name, every, osc, initial_state(1.0, 0.0), 1.5, &stats);
    CHECK(static_cast<long>(all.size()) == stats.steps + 1);
    CHECK(all.back().s.t == 1.5);
  }
}

TEST_CASE("generalized-alpha with rho_infinity = 1 is Newmark", "[integrator]") {
  Pendulum p;
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = 0.01;
  o.output_interval = 0.5;
  o.rho_infinity = 1.0;
  const auto a = run("newmark", o, p, initial_state(1.0, 0.0), 3.0);
  const auto b = run("generalized-alpha", o, p, initial_state(1.0, 0.0), 3.0);
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) CHECK(std::abs(a[k].s.q[0] - b[k].s.q[0]) < 1e-12);
}

TEST_CASE("generalized-alpha damps a high frequency that Newmark keeps", "[integrator]") {
  // Steps of h·w = 100: Newmark's amplification is exactly 1 in modulus, the
  // generalized-alpha's about rho_infinity. Energy measure: q² + (qd/w)².
  const double w = 1000.0;
  Oscillator fast(w);
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = 0.1;
  o.relative_tolerance = o.absolute_tolerance = 1e-12;
  o.rho_infinity = 0.5;
  auto energy = [w](const Sample& s) { return s.s.q[0] * s.s.q[0] + std::pow(s.s.qd[0] / w, 2); };
  const auto n = run("newmark", o, fast, initial_state(1.0, 0.0), 3.0);
  const auto g = run("generalized-alpha", o, fast, initial_state(1.0, 0.0), 3.0);
  CHECK(std::abs(energy(n.back()) - 1.0) < 1e-9);
  // 30 steps at |R| ~ 0.5 leave an energy ~ 0.25^30 ~ 1e-18, times the known
  // overshoot of the first steps (a factor ~40 here).
  CHECK(energy(g.back()) < 1e-10);
}

// The steps of a run, the final state and the outputs seen.
struct Trace {
  Statistics stats;
  State end;
  std::vector<double> progress;  // after each step (stepping integrators) or output
};

Trace trace(const std::string& name, double interval) {
  Pendulum p;
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = 1e-7;
  o.output_interval = interval;
  if (name == "rk4" || name == "midpoint") o.initial_step = 2e-3;
  Trace t;
  o.on_progress = [&t](double time, double, double) { t.progress.push_back(time); };
  auto integ = make_integrator(name, o);
  t.end = integ->integrate(p, initial_state(2.5, 0.0), 10.0);
  t.stats = integ->statistics();
  return t;
}

TEST_CASE("the output interval never changes the steps taken", "[integrator][output]") {
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    const Trace none = trace(name, 0.0);  // every step delivered
    for (double interval : {1e-3, 1e-2}) {
      CAPTURE(interval);
      const Trace t = trace(name, interval);
      CHECK(t.stats.steps == none.stats.steps);
      CHECK(t.stats.rejected_steps == none.stats.rejected_steps);
      CHECK(t.end.t == none.end.t);
      CHECK(t.end.q == none.end.q);  // bit for bit
      CHECK(t.end.qd == none.end.qd);
    }
    CHECK(none.stats.steps > 20);
  }
}

TEST_CASE("dense output is as accurate as the steps", "[integrator][output]") {
  // The worst error in q, qd and qdd at outputs every 1e-3 s (between steps of ~1e-2
  // s) against the worst at the step ends themselves: the interpolants of rk4
  // (quintic Hermite) and dop853 (order 7 for an order-8 method) lose a factor 3 to 4.
  Oscillator osc;
  auto worst_error = [&](const std::string& name, double interval) {
    IntegratorOptions o = tight(name, 1e-8, interval);
    if (name == "rk4" || name == "midpoint") o.initial_step = 1e-2;
    double worst = 0.0;
    for (const auto& s : run(name, o, osc, initial_state(1.0, 0.0), 1.0)) {
      const double t = s.s.t;
      worst = std::max(
          {worst, std::abs(s.s.q[0] - std::cos(two_pi * t)),
           std::abs(s.s.qd[0] + two_pi * std::sin(two_pi * t)) / two_pi,
           std::abs(s.qdd[0] + two_pi * two_pi * std::cos(two_pi * t)) / (two_pi * two_pi)});
    }
    return worst;
  };
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    const double at_steps = worst_error(name, 0.0);
    const double dense = worst_error(name, 1e-3);
    INFO(fmt::format("worst error at the steps {:.3e}, at the outputs {:.3e}", at_steps, dense));
    CHECK(dense < 5.0 * at_steps);
  }
}

TEST_CASE("q_scale sets the error weight of each coordinate, never |q|", "[integrator][weights]") {
  IntegratorOptions o;
  o.relative_tolerance = 1e-6;
  o.absolute_tolerance = 1e-9;
  ErrorWeights unit(o, "test", 2, 1);
  State a, b;
  a.q = Eigen::Vector2d(1000.0, -3.0);
  a.qd = Eigen::Vector2d(50.0, 0.0);
  a.y = Vector::Constant(1, -2.0);
  b = a;
  b.qd[1] = -4.0;
  const Vector& w = unit.update(a, b);
  CHECK(w[0] == 1e-9 + 1e-6);  // q: the unit scale, whatever |q| = 1000
  CHECK(w[1] == 1e-9 + 1e-6);
  CHECK(w[2] == 1e-9 + 1e-6 * 50.0);  // qd: largest magnitude at either end
  CHECK(w[3] == 1e-9 + 1e-6 * 4.0);
  CHECK(w[4] == 1e-9 + 1e-6 * 2.0);  // y
  Vector e(5);
  e << 1e-6, 0.0, 0.0, 0.0, 0.0;
  CHECK(unit.rms(e) == Approx(1e-6 / w[0] / std::sqrt(5.0)));

  o.q_scale = {0.1, 10.0};
  ErrorWeights scaled(o, "test", 2, 1);
  CHECK(scaled.update(a, b)[0] == 1e-9 + 1e-6 * 0.1);
  CHECK(scaled.weights()[1] == 1e-9 + 1e-6 * 10.0);
}

TEST_CASE("a larger q_scale loosens the position error test", "[integrator][weights]") {
  Pendulum p;
  auto steps = [&](std::vector<double> scale) {
    IntegratorOptions o;
    o.relative_tolerance = 1e-8;
    o.absolute_tolerance = 1e-14;
    o.q_scale = std::move(scale);
    auto integ = make_integrator("newmark", o);
    integ->integrate(p, initial_state(1.0, 0.0), 5.0);
    return integ->statistics().steps;
  };
  CHECK(steps({100.0}) < steps({}));
  CHECK(steps({}) < steps({0.01}));
}

}  // namespace

// global_tolerance bounds the error of every output, not of each step: the run is
// repeated at tighter tolerances, and only the last run's outputs are delivered.
TEST_CASE("global_tolerance bounds the error at every output of 20 periods",
          "[integrator][global]") {
  Oscillator osc;
  // |q - cos 2 pi t| and |qd + 2 pi sin 2 pi t| over the outputs.
  const auto worst_error = [](const std::vector<Sample>& out) {
    double worst = 0.0;
    for (const Sample& o : out) {
      const double t = o.s.t;
      worst = std::max({worst, std::abs(o.s.q[0] - std::cos(two_pi * t)),
                        std::abs(o.s.qd[0] + two_pi * std::sin(two_pi * t))});
    }
    return worst;
  };
  for (const std::string name : {"dopri5", "dop853", "cvode"}) {
    CAPTURE(name);
    IntegratorOptions o = tight(name, 1e-5, 0.1);
    Statistics local, global;
    const double local_error =
        worst_error(run(name, o, osc, initial_state(1.0, 0.0), 20.0, &local));
    o.global_tolerance = 1e-6;
    const auto out = run(name, o, osc, initial_state(1.0, 0.0), 20.0, &global);
    INFO("error " << local_error << " in " << local.steps << " steps; with global_tolerance "
                  << worst_error(out) << " (estimated " << global.global_error_estimate << ") in "
                  << global.runs << " runs, the last at " << global.last_relative_tolerance);
    CHECK(local_error > 1e-6);   // the step tolerance alone does not hold it
    REQUIRE(out.size() == 201);  // one run's outputs
    CHECK(worst_error(out) < 1e-6);
    CHECK(global.global_error_estimate <= 1e-6);
    CHECK(global.runs >= 2);
    CHECK(global.steps > local.steps);  // every run's work counted
  }
  // An output at every step: the last run's steps, once, in order.
  IntegratorOptions every = tight("dopri5", 1e-5, 0.0);
  every.global_tolerance = 1e-6;
  const auto steps = run("dopri5", every, osc, initial_state(1.0, 0.0), 20.0);
  REQUIRE(steps.size() > 2);
  CHECK(steps.front().s.t == 0.0);
  CHECK(steps.back().s.t == 20.0);
  const auto not_after = [](const Sample& a, const Sample& b) { return !(b.s.t > a.s.t); };
  CHECK(std::adjacent_find(steps.begin(), steps.end(), not_after) == steps.end());
  CHECK(worst_error(steps) < 1e-6);
  IntegratorOptions bad = tight("dopri5", 1e-6, 0.1);
  bad.global_tolerance = -1.0;
  CHECK_THROWS_AS(make_integrator("dopri5", bad)->integrate(osc, initial_state(1.0, 0.0), 1.0),
                  OptionError);
}

TEST_CASE("a global_tolerance out of reach is refused, naming it", "[integrator][global]") {
  Oscillator osc;
  IntegratorOptions o = tight("dopri5", 1e-6, 0.0);
  o.global_tolerance = 1e-17;  // below rounding: no local tolerance gets there
  Statistics stats;
  CHECK_THROWS_WITH(run("dopri5", o, osc, initial_state(1.0, 0.0), 2.0, &stats),
                    Catch::Matchers::Contains("global_tolerance 1e-17 not reached"));
}

// At a fixed step the tolerance changes nothing: global_tolerance halves the step
// instead, and Richardson's estimate from the last runs is the error of the result.
TEST_CASE(
    "global_tolerance at a fixed step: halved steps, an estimate within a factor 10, met when said",
    "[integrator][global]") {
  Oscillator osc;
  const auto worst_error = [](const std::vector<Sample>& out) {
    double worst = 0.0;
    for (const Sample& o : out) {
      const double t = o.s.t;
      worst = std::max({worst, std::abs(o.s.q[0] - std::cos(two_pi * t)),
                        std::abs(o.s.qd[0] + two_pi * std::sin(two_pi * t))});
    }
    return worst;
  };
  struct Case {
    std::string name;
    double step;
    bool fixed_step;
  };
  for (const Case& c : {Case{"rk4", 0.01, false}, Case{"midpoint", 0.01, false},
                        Case{"newmark", 0.01, true}, Case{"generalized-alpha", 0.01, true},
                        Case{"dopri5", 0.05, true}, Case{"dop853", 0.1, true}}) {
    CAPTURE(c.name);
    IntegratorOptions o;
    o.initial_step = c.step;
    o.fixed_step = c.fixed_step;
    o.output_interval = 0.1;
    Statistics plain, global;
    run(c.name, o, osc, initial_state(1.0, 0.0), 5.0, &plain);
    CHECK(std::isnan(plain.global_error_estimate));  // none asked, none given
    CHECK_FALSE(plain.global_tolerance_met);
    o.global_tolerance = 1e-6;
    const auto out = run(c.name, o, osc, initial_state(1.0, 0.0), 5.0, &global);
    const double error = worst_error(out);
    INFO(fmt::format("error {:.3g}, estimate {:.3g}, {} runs, the last at h = {:g}", error,
                     global.global_error_estimate, global.runs, global.last_step));
    REQUIRE(out.size() == 51);  // one run's outputs
    CHECK(global.global_tolerance_met);
    CHECK(global.runs >= 3);
    CHECK(global.global_error_estimate <= 1e-6);
    CHECK(error <= 1e-6);
    CHECK(std::max(global.global_error_estimate, 1e-12) <= 10.0 * std::max(error, 1e-12));
    CHECK(std::max(error, 1e-12) <= 10.0 * std::max(global.global_error_estimate, 1e-12));
  }
}

TEST_CASE("global_tolerance at a fixed step out of reach is refused, naming what was reached",
          "[integrator][global]") {
  Oscillator osc;
  IntegratorOptions o;
  o.initial_step = 0.01;
  o.global_tolerance = 1e-17;  // below rounding: no step gets there
  CHECK_THROWS_WITH(run("rk4", o, osc, initial_state(1.0, 0.0), 1.0),
                    Catch::Matchers::StartsWith(
                        "integrator 'rk4': global_tolerance 1e-17 not reached by step halving "
                        "from initial_step 0.01 (the rounding of its 400 steps, up to ") &&
                        Catch::Matchers::Contains(
                            "is above it): the result at a step of 0.0025 s is estimated "));
  o.global_tolerance = 1e-9;
  o.max_steps = 150;
  CHECK_THROWS_WITH(run("rk4", o, osc, initial_state(1.0, 0.0), 1.0),
                    "integrator 'rk4': global_tolerance 1e-09 not reached by step halving "
                    "from initial_step 0.01 (a step of 0.005 s would take more than "
                    "max_steps 150): 1 run(s), down to a step of 0.01 s, too few for an "
                    "estimate");
}
