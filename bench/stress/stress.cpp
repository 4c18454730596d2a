// Long and hard runs, each reporting what it measured (bench/results/stress.md):
//
//   energy_drift    the double pendulum from its horizontal release (chaotic) over
//                   10 000 s, every integrator: largest |E - E0| over the first and
//                   the last 1 000 s;
//   chaos           the same release: dop853 and dopri5 (and cvode) at 1e-12 and
//                   1e-13; the first time two of them differ by more than 1e-6;
//   slider_crank    the slider-crank scenario through 1 000 revolutions (160 s from
//                   50 rad/s): final error against dop853 at 1e-13 and energy drift;
//   spin            robot3d, its wrist spun at 1e4 rad/s, no forces but gravity, 1 s:
//                   energy and the angular momentum about the turret axis (z) must stay;
//   trike           the trike scenario (stiff tyres, suspensions) with every integrator:
//                   completes or fails (the message), steps, rejected steps, CPU.
//
//   symdyn_bench_stress [NAME...]     (none: all of them)
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "../work_precision/problems.hpp"
#include "robot3d_absolute.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using symdyn::runtime::IntegratorOptions;
using symdyn::runtime::MultibodySystem;
using symdyn::runtime::State;
using symdyn::runtime::Statistics;
using symdyn::runtime::Vector;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

using System = symdyn::bench::ProblemSystem;

System scenario_system(const std::string& model) {
  if (model == "double_pendulum") return symdyn::bench::double_pendulum_problem();
  return symdyn::bench::slider_crank_problem();
}

// One integrator setting: a tolerance (rtol = atol), or a fixed step for rk4 and midpoint.
struct Setting {
  std::string integrator;
  double value;
  bool fixed() const { return integrator == "rk4" || integrator == "midpoint"; }
  std::string text() const {
    return fmt::format("{} {}={:g}", integrator, fixed() ? "h" : "tol", value);
  }
};

IntegratorOptions options(const Setting& s) {
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = s.fixed() ? 1e-6 : s.value;
  if (s.fixed()) o.initial_step = s.value;
  return o;
}

double max_difference(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

void energy_drift() {
  fmt::print("## energy_drift: double pendulum, horizontal release, 10 000 s\n\n");
  fmt::print(
      "| integrator | first 1 000 s: max abs(E - E0) (J) | last 1 000 s (J) | steps | CPU s "
      "|\n|---|---:|---:|---:|---:|\n");
  const double t_end = 1e4;
  for (const Setting& set : std::vector<Setting>{{"dop853", 1e-10},
                                                 {"dopri5", 1e-10},
                                                 {"cvode", 1e-10},
                                                 {"arkode", 1e-8},
                                                 {"newmark", 1e-6},
                                                 {"generalized-alpha", 1e-6},
                                                 {"rk4", 1e-2},
                                                 {"midpoint", 1e-2}}) {
    System s = scenario_system("double_pendulum");
    const double e0 = s.system->energies(s.initial).total();
    double first = 0.0, last = 0.0;
    IntegratorOptions o = options(set);
    o.output_interval = 0.5;
    o.on_output = [&](const State& x, const Vector&, const Vector&) {
      const double error = std::abs(s.system->energies(x).total() - e0);
      if (x.t <= 1000.0) first = std::max(first, error);
      if (x.t >= t_end - 1000.0) last = std::max(last, error);
    };
    auto integ = symdyn::runtime::make_integrator(set.integrator, o);
    const double t0 = cpu_seconds();
    try {
      integ->integrate(*s.system, s.initial, t_end);
      fmt::print("| {} | {:.2e} | {:.2e} | {} | {:.1f} |\n", set.text(), first, last,
                 integ->statistics().steps, cpu_seconds() - t0);
    } catch (const std::exception& e) {
      fmt::print("| {} | fails: {} | | | |\n", set.text(), e.what());
    }
    std::fflush(stdout);
  }
  fmt::print("\n");
}

// The states of a run every 0.01 s.
std::vector<State> trajectory(System& s, const Setting& set, double t_end) {
  std::vector<State> out;
  IntegratorOptions o = options(set);
  o.output_interval = 0.01;
  o.on_output = [&](const State& x, const Vector&, const Vector&) { out.push_back(x); };
  symdyn::runtime::make_integrator(set.integrator, o)->integrate(*s.system, s.initial, t_end);
  return out;
}

// The first output time at which two trajectories differ by more than `bound`.
double divergence_time(const std::vector<State>& a, const std::vector<State>& b, double bound) {
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
    if (max_difference(a[k], b[k]) > bound) return a[k].t;
  }
  return std::numeric_limits<double>::infinity();
}

void chaos() {
  fmt::print(
      "## chaos: double pendulum, horizontal release: when do two tight runs part by 1e-6?\n\n");
  fmt::print(
      "| run A | run B | first t with max(abs(q_A - q_B), abs(qd_A - qd_B)) > 1e-6 (s) | > 1e-2 "
      "(s) |\n|---|---|---:|---:|\n");
  System s = scenario_system("double_pendulum");
  const double t_end = 60.0;
  const std::vector<Setting> runs = {
      {"dop853", 1e-13}, {"dopri5", 1e-13}, {"dop853", 1e-12}, {"cvode", 1e-12}};
  std::vector<std::vector<State>> traj;
  for (const Setting& r : runs) traj.push_back(trajectory(s, r, t_end));
  for (std::size_t b = 1; b < runs.size(); ++b) {
    fmt::print("| {} | {} | {:.2f} | {:.2f} |\n", runs[0].text(), runs[b].text(),
               divergence_time(traj[0], traj[b], 1e-6), divergence_time(traj[0], traj[b], 1e-2));
  }
  fmt::print("\n");
}

void slider_crank() {
  // The crank slows where the linkage is heavy: 1 000 turns take 160 s, not 2·pi·1000/50.
  const double t_end = 160.0;
  fmt::print("## slider_crank: 1 000 revolutions ({:.1f} s)\n\n", t_end);
  System s = scenario_system("slider_crank");
  auto solve = [&](const Setting& set, Statistics* st = nullptr) {
    IntegratorOptions o = options(set);
    o.output_times = {t_end};
    auto integ = symdyn::runtime::make_integrator(set.integrator, o);
    State end = integ->integrate(*s.system, s.initial, t_end);
    if (st != nullptr) *st = integ->statistics();
    return end;
  };
  const State ref = solve({"dop853", 1e-13});
  const State check = solve({"dopri5", 1e-13});
  const double e0 = s.system->energies(s.initial).total();
  fmt::print(
      "Reference dop853 at 1e-13: crank angle {:.6f} rad ({:.1f} turns), agreement with dopri5 at "
      "1e-13: {:.1e}; E0 = {:.6g} J.\n\n",
      ref.q(0), ref.q(0) / (2 * std::numbers::pi), max_difference(ref, check), e0);
  fmt::print(
      "| setting | final error | relative abs(E(t_end) - E0) / E0 | steps | rejected | CPU s "
      "|\n|---|---:|---:|---:|---:|---:|\n");
  for (const Setting& set : std::vector<Setting>{{"dop853", 1e-10},
                                                 {"dopri5", 1e-10},
                                                 {"cvode", 1e-10},
                                                 {"arkode", 1e-8},
                                                 {"newmark", 1e-8},
                                                 {"generalized-alpha", 1e-8},
                                                 {"rk4", 1e-4},
                                                 {"midpoint", 1e-4}}) {
    Statistics st;
    const double t0 = cpu_seconds();
    try {
      const State end = solve(set, &st);
      fmt::print("| {} | {:.2e} | {:.2e} | {} | {} | {:.1f} |\n", set.text(),
                 max_difference(end, ref),
                 std::abs(s.system->energies(end).total() - e0) / std::abs(e0), st.steps,
                 st.rejected_steps, cpu_seconds() - t0);
    } catch (const std::exception& e) {
      fmt::print("| {} | fails: {} | | | | |\n", set.text(), e.what());
    }
    std::fflush(stdout);
  }
  fmt::print("\n");
}

void spin() {
  fmt::print("## spin: robot3d, wrist at 1e4 rad/s, turret at 1 rad/s, gravity only, 1 s\n\n");
  fmt::print(
      "| setting | max relative abs(E - E0) | max abs(L_z - L_z0) / norm(L0) | steps | CPU s "
      "|\n|---|---:|---:|---:|---:|\n");
  for (const Setting& set : std::vector<Setting>{{"dop853", 1e-12},
                                                 {"dop853", 1e-10},
                                                 {"dopri5", 1e-10},
                                                 {"cvode", 1e-10},
                                                 {"midpoint", 1e-5},
                                                 {"rk4", 1e-5}}) {
    MultibodySystem sys(symdyn::runtime::Model::from<symdyn_generated::robot3d_absolute>(),
                        symdyn::runtime::EquationsSource::emitted);
    State x0 = sys.initial_state();
    x0.q << 0.0, 0.3, 0.6, 0.0, 0.2;
    x0.qd << 1.0, 0.0, 0.0, 1e4, 0.0;
    const double e0 = sys.energies(x0).total(), l0 = sys.momentum(x0).angular.z();
    const double l_scale =
        sys.momentum(x0).angular.norm();  // L_z0 alone is small beside the spin's momentum
    double de = 0.0, dl = 0.0;
    IntegratorOptions o = options(set);
    o.output_interval = 1e-3;
    o.on_output = [&](const State& x, const Vector&, const Vector&) {
      de = std::max(de, std::abs(sys.energies(x).total() - e0) / std::abs(e0));
      dl = std::max(dl, std::abs(sys.momentum(x).angular.z() - l0) / l_scale);
    };
    auto integ = symdyn::runtime::make_integrator(set.integrator, o);
    const double t0 = cpu_seconds();
    try {
      integ->integrate(sys, x0, 1.0);
      fmt::print("| {} | {:.2e} | {:.2e} | {} | {:.2f} |\n", set.text(), de, dl,
                 integ->statistics().steps, cpu_seconds() - t0);
    } catch (const std::exception& e) {
      fmt::print("| {} | fails: {} | | | |\n", set.text(), e.what());
    }
    std::fflush(stdout);
  }
  fmt::print("\n");
}

// The trike's scenario (models/scenarios/trike.json) run with `set` over 5 s.
symdyn::sim::RunResult run_trike(const Setting& set) {
  symdyn::sim::RunOptions ro;
  ro.t_end = 5.0;
  ro.integrator = set.integrator;
  ro.output_interval = 5.0;
  if (set.fixed())
    ro.step = set.value;
  else
    ro.tolerance = set.value;
  symdyn::sim::Simulation sim(symdyn::sim::find_builtin("trike"), ro);
  return sim.run();
}

void trike() {
  fmt::print("## trike: its scenario (tyres 2e5 N/m, suspensions, steering, drive), 5 s\n\n");
  const State ref = run_trike({"dop853", 1e-12}).final;
  fmt::print(
      "Reference: dop853 at 1e-12.\n\n| setting | outcome | final error | steps | rejected | "
      "accelerations | Jacobians | CPU ms |\n|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (const Setting& set : std::vector<Setting>{{"dopri5", 1e-6},
                                                 {"dop853", 1e-6},
                                                 {"cvode", 1e-6},
                                                 {"arkode", 1e-6},
                                                 {"newmark", 1e-6},
                                                 {"generalized-alpha", 1e-6},
                                                 {"rk4", 1e-2},
                                                 {"rk4", 1.0 / 30},
                                                 {"midpoint", 1e-2},
                                                 {"midpoint", 1e-3}}) {
    const double t0 = cpu_seconds();
    std::string outcome = "completes", error = "";
    Statistics st;
    try {
      const symdyn::sim::RunResult r = run_trike(set);
      st = r.statistics;
      error = fmt::format("{:.2e}", max_difference(r.final, ref));
    } catch (const std::exception& e) {
      outcome = fmt::format("fails: {}", e.what());
    }
    fmt::print("| {} | {} | {} | {} | {} | {} | {} | {:.3g} |\n", set.text(), outcome, error,
               st.steps, st.rejected_steps, st.rhs_evaluations, st.jacobian_evaluations,
               1e3 * (cpu_seconds() - t0));
    std::fflush(stdout);
  }
  fmt::print("\n");
}

}  // namespace

int main(int argc, char** argv) try {
  const std::vector<std::pair<std::string, std::function<void()>>> tests = {
      {"chaos", chaos},
      {"spin", spin},
      {"trike", trike},
      {"slider_crank", slider_crank},
      {"energy_drift", energy_drift}};
  std::vector<std::string> chosen(argv + 1, argv + argc);
  for (const auto& [name, run] : tests) {
    if (chosen.empty() || std::find(chosen.begin(), chosen.end(), name) != chosen.end()) run();
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "symdyn_bench_stress: %s\n", e.what());
  return 1;
}
