// Implicit integrators with exact Jacobians against differenced ones, on the
// scenarios of models/scenarios run as symdyn-sim runs them (force elements
// included): Newmark on the trike and on amru5 walking, CVODE on the
// slider-crank, the trike and amru5, midpoint on the trike. Each problem and
// tolerance runs in one process, interleaved: with the emitted derivatives and the
// force elements' own (MultibodySystem's default: "exact"); with the emitted
// derivatives but every force element's part by central differences of its Q
// (set_exact_load_derivatives(false): "elements differenced"; the trike's tyres,
// amru5's contacts); then after set_exact_jacobians(false) ("differences"), where
// Newmark's iteration matrix takes C and K from central differences of the
// residual (4·nq residuals per matrix), CVODE falls back to its forward
// differences of the accelerations (2·nq calls per Jacobian, counted among its
// evaluations) and midpoint differences its map (2n + 1 maps per matrix).
// Before the runs of a problem, one Jacobian (MultibodySystem::jacobians) is timed
// in the three ways at the end state of its scenario.
//
//   symdyn_bench_implicit_jacobians [--reps N] [--problem NAME]... [--integrator NAME]
//   [--tolerance TOL] [--mode exact|elements|differences] [--no-reference]
//
// --integrator, --tolerance, --mode: those runs alone (with --mode, no Jacobian
// timed); --no-reference: no reference
// run (errors are NaN), for a quick look or a profile of the runs alone (valgrind
// --tool=callgrind --toggle-collect='*SteppingIntegrator::run*' with --reps 1).
//
// Output: tab-separated rows on stdout,
//   reference <problem> <integrator> <tol> <agreement> <cpu_s>
//   jacobian <problem> <exact|elements differenced|differences> <us> <calls> <method>
//   run <problem> <integrator> <tol> <exact|elements differenced|differences> <error> <cpu_ms>
//       <steps> <rejected> <newton> <residuals> <rhs> <jacobians> <method>
// error: the largest |q - q_ref|, |qd - qd_ref| at t_end against dop853 at
// rtol = atol = 1e-12 (agreement: its distance to dopri5 at 1e-12); cpu_ms: the
// median over N repetitions (5) of the process CPU time of one run (the
// scenario's set-up excluded), interleaved (exact, elements differenced,
// differences, exact, ...); tol of midpoint: its fixed step; us: the median over
// 21 rounds of the CPU time of one Jacobian.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using symdyn::runtime::State;
using symdyn::runtime::Statistics;

struct Problem {
  std::string name;
  std::string scenario;  // models/scenarios/<scenario>.json
  double t_end;
  std::string integrator;
  std::vector<double> tolerances;  // midpoint: fixed steps
};

// amru5 over one gait period (the scenario's 10 s are five), the trike and the
// slider-crank over their scenarios' intervals; CVODE also on the trike and
// amru5, whose scenarios choose it.
const Problem all_problems[] = {
    {"trike_5s", "trike", 5.0, "newmark", {1e-4, 1e-6}},
    {"amru5_2s", "amru5", 2.0, "newmark", {1e-4, 1e-6}},
    {"slider_crank_1s", "slider_crank", 1.0, "cvode", {1e-6, 1e-9}},
    {"trike_5s", "trike", 5.0, "cvode", {1e-6}},
    {"amru5_2s", "amru5", 2.0, "cvode", {1e-6}},
    {"trike_1s", "trike", 1.0, "midpoint", {2e-3}},
};

// How the Jacobians are obtained: a row's label and the system's switches.
struct Mode {
  const char* label;
  const char* option;  // its name for --mode
  bool exact_jacobians, exact_loads;
};
const Mode modes[] = {
    {"exact", "exact", true, true},
    {"elements differenced", "elements", true, false},
    {"differences", "differences", false, false},
};

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Outcome {
  State final;
  Statistics stats;
  std::string method;
  double cpu = 0.0;  // s
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size()) / 2, v.end());
  return v[v.size() / 2];
}

void configure(symdyn::runtime::MultibodySystem& system, const Mode& mode) {
  system.set_exact_jacobians(mode.exact_jacobians);
  system.set_exact_load_derivatives(mode.exact_loads);
}

Outcome run(const Problem& p, const std::string& integrator, double tolerance, const Mode& mode) {
  symdyn::sim::RunOptions o;
  o.t_end = p.t_end;
  o.integrator = integrator;
  if (integrator == "midpoint") {
    o.step = tolerance;
  } else {
    o.tolerance = tolerance;
  }
  o.output_interval = p.t_end;
  symdyn::sim::Simulation sim(symdyn::sim::find_builtin(p.scenario), o);
  configure(sim.system(), mode);
  const double start = cpu_seconds();
  const symdyn::sim::RunResult r = sim.run();
  // CVODE without exact derivatives differences the accelerations itself (sundials_support.cpp),
  // midpoint its map.
  std::string method = sim.system().jacobian_method();
  if (!mode.exact_jacobians && integrator == "cvode") {
    method = "CVODE's forward differences of the accelerations";
  } else if (!mode.exact_jacobians && integrator == "midpoint") {
    method = "forward differences of midpoint's map";
  }
  return {r.final, r.statistics, method, cpu_seconds() - start};
}

// One Jacobian of the scenario's system at its end state s, timed in each mode.
void time_jacobians(const Problem& p, const State& s) {
  symdyn::sim::Simulation sim(symdyn::sim::find_builtin(p.scenario));
  symdyn::runtime::MultibodySystem& system = sim.system();
  symdyn::runtime::Vector qdd, yd;
  system.accelerations(s, qdd, yd);
  symdyn::runtime::Matrix M, C, K;
  constexpr int rounds = 21;
  // Calls per round: about 2 ms of the exact Jacobian.
  system.jacobians(s, qdd, M, C, K);
  const double once = cpu_seconds();
  system.jacobians(s, qdd, M, C, K);
  const int calls =
      std::clamp(static_cast<int>(2e-3 / std::max(cpu_seconds() - once, 1e-9)), 1, 1000);
  std::vector<double> times[std::size(modes)];
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t m = 0; m < std::size(modes); ++m) {
      configure(system, modes[m]);
      const double start = cpu_seconds();
      for (int c = 0; c < calls; ++c) system.jacobians(s, qdd, M, C, K);
      times[m].push_back((cpu_seconds() - start) / calls);
    }
  }
  for (std::size_t m = 0; m < std::size(modes); ++m) {
    configure(system, modes[m]);
    fmt::print("jacobian\t{}\t{}\t{:.2f}\t{}\t{}\n", p.name, modes[m].label, 1e6 * median(times[m]),
               calls, system.jacobian_method());
  }
  std::fflush(stdout);
}

double distance(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

struct Options {
  int reps = 5;
  std::vector<std::string> problems;
  std::string integrator;  // "": every integrator
  double tolerance = 0.0;  // 0: every tolerance of the problem
  std::string mode;        // "": every mode
  bool reference = true;
};

void measure(const Problem& p, const Options& options) {
  const int reps = options.reps;
  // One reference and one timing of the Jacobians per problem name, at its first integrator.
  static std::map<std::string, State> references;
  if (!references.contains(p.name)) {
    State ref = run(p, p.integrator, p.tolerances.front(), modes[0]).final;
    if (options.reference) {
      const double start = cpu_seconds();
      ref = run(p, "dop853", 1e-12, modes[0]).final;
      const State check = run(p, "dopri5", 1e-12, modes[0]).final;
      fmt::print("reference\t{}\tdop853\t1e-12\t{:.3g}\t{:.1f}\n", p.name, distance(ref, check),
                 cpu_seconds() - start);
      std::fflush(stdout);
    }
    references[p.name] = ref;
    if (options.mode.empty()) time_jacobians(p, ref);
  }
  const State ref = references.at(p.name);
  constexpr std::size_t n_modes = std::size(modes);
  for (double tol : p.tolerances) {
    if (options.tolerance > 0.0 && tol != options.tolerance) continue;
    const auto chosen = [&](std::size_t m) {
      return options.mode.empty() || options.mode == modes[m].option;
    };
    Outcome last[n_modes];
    std::vector<double> cpu[n_modes];
    for (int r = 0; r < reps; ++r) {
      for (std::size_t m = 0; m < n_modes; ++m) {
        if (!chosen(m)) continue;
        last[m] = run(p, p.integrator, tol, modes[m]);
        cpu[m].push_back(last[m].cpu);
      }
    }
    for (std::size_t m = 0; m < n_modes; ++m) {
      if (!chosen(m)) continue;
      const Outcome& o = last[m];
      const Statistics& s = o.stats;
      fmt::print("run\t{}\t{}\t{:g}\t{}\t{:.3g}\t{:.2f}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", p.name,
                 p.integrator, tol, modes[m].label,
                 options.reference ? distance(o.final, ref) : std::nan(""), 1e3 * median(cpu[m]),
                 s.steps, s.rejected_steps, s.newton_iterations, s.residual_evaluations,
                 s.rhs_evaluations, s.jacobian_evaluations, o.method);
    }
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) {
      o.reps = std::stoi(argv[++i]);
    } else if (a == "--problem" && i + 1 < argc) {
      o.problems.emplace_back(argv[++i]);
    } else if (a == "--integrator" && i + 1 < argc) {
      o.integrator = argv[++i];
    } else if (a == "--tolerance" && i + 1 < argc) {
      o.tolerance = std::stod(argv[++i]);
    } else if (a == "--mode" && i + 1 < argc) {
      o.mode = argv[++i];
    } else if (a == "--no-reference") {
      o.reference = false;
    } else {
      fmt::print(
          stderr,
          "usage: symdyn_bench_implicit_jacobians [--reps N] [--problem NAME]... [--integrator "
          "NAME] [--tolerance TOL] [--mode exact|elements|differences] [--no-reference]\n");
      return 2;
    }
  }
  try {
    for (const Problem& p : all_problems) {
      const bool named = o.problems.empty() || std::find(o.problems.begin(), o.problems.end(),
                                                         p.name) != o.problems.end();
      if (named && (o.integrator.empty() || o.integrator == p.integrator)) {
        measure(p, o);
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "symdyn_bench_implicit_jacobians: {}\n", e.what());
    return 1;
  }
  return 0;
}
