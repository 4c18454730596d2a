// Implicit integrators with exact Jacobians against differenced ones, on the
// scenarios of models/scenarios run as symdyn-sim runs them (force elements
// included): Newmark on the trike and on amru5 walking, CVODE on the
// slider-crank, the trike and amru5. Each problem and tolerance runs twice in
// one process: with the emitted derivatives (MultibodySystem's default), then after
// set_exact_jacobians(false), where Newmark's iteration matrix takes C and K from
// central differences of the residual (4·nq residuals per matrix) and CVODE
// falls back to its forward differences of the accelerations (2·nq calls per
// Jacobian, counted among its evaluations).
//
//   symdyn_bench_implicit_jacobians [--reps N] [--problem NAME]... [--tolerance TOL]
//   [--no-reference]
//
// --tolerance: that tolerance alone; --no-reference: no reference run (errors
// are NaN), for a quick look or a profile of the runs alone.
//
// Output: tab-separated rows on stdout,
//   reference <problem> <integrator> <tol> <agreement> <cpu_s>
//   run <problem> <integrator> <tol> <exact|differences> <error> <cpu_ms> <steps> <rejected>
//       <newton> <residuals> <rhs> <jacobians> <method>
// error: the largest |q - q_ref|, |qd - qd_ref| at t_end against dop853 at
// rtol = atol = 1e-12 (agreement: its distance to dopri5 at 1e-12); cpu_ms: the
// median over N repetitions (5) of the process CPU time of one run (the
// scenario's set-up excluded), interleaved
// (exact, differences, exact, ...).
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
  std::vector<double> tolerances;
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

Outcome run(const Problem& p, const std::string& integrator, double tolerance, bool exact) {
  symdyn::sim::RunOptions o;
  o.t_end = p.t_end;
  o.integrator = integrator;
  o.tolerance = tolerance;
  o.output_interval = p.t_end;
  symdyn::sim::Simulation sim(symdyn::sim::find_builtin(p.scenario), o);
  sim.system().set_exact_jacobians(exact);
  const double start = cpu_seconds();
  const symdyn::sim::RunResult r = sim.run();
  // CVODE without exact derivatives differences the accelerations itself (sundials_support.cpp).
  const std::string method = !exact && integrator == "cvode"
                                 ? "CVODE's forward differences of the accelerations"
                                 : sim.system().jacobian_method();
  return {r.final, r.statistics, method, cpu_seconds() - start};
}

double distance(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size()) / 2, v.end());
  return v[v.size() / 2];
}

struct Options {
  int reps = 5;
  std::vector<std::string> problems;
  double tolerance = 0.0;  // 0: every tolerance of the problem
  bool reference = true;
};

void measure(const Problem& p, const Options& options) {
  const int reps = options.reps;
  // One reference per problem name, computed at its first integrator.
  static std::map<std::string, State> references;
  if (options.reference && !references.contains(p.name)) {
    const double start = cpu_seconds();
    const State ref = run(p, "dop853", 1e-12, true).final;
    const State check = run(p, "dopri5", 1e-12, true).final;
    fmt::print("reference\t{}\tdop853\t1e-12\t{:.3g}\t{:.1f}\n", p.name, distance(ref, check),
               cpu_seconds() - start);
    std::fflush(stdout);
    references[p.name] = ref;
  }
  const State ref = options.reference ? references.at(p.name) : State{};
  for (double tol : p.tolerances) {
    if (options.tolerance > 0.0 && tol != options.tolerance) continue;
    Outcome last[2];
    std::vector<double> cpu[2];
    for (int r = 0; r < reps; ++r) {
      for (int exact = 1; exact >= 0; --exact) {
        last[exact] = run(p, p.integrator, tol, exact == 1);
        cpu[exact].push_back(last[exact].cpu);
      }
    }
    for (int exact = 1; exact >= 0; --exact) {
      const Outcome& o = last[exact];
      const Statistics& s = o.stats;
      fmt::print("run\t{}\t{}\t{:g}\t{}\t{:.3g}\t{:.2f}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", p.name,
                 p.integrator, tol, exact ? "exact" : "differences",
                 options.reference ? distance(o.final, ref) : std::nan(""),
                 1e3 * median(cpu[exact]), s.steps, s.rejected_steps, s.newton_iterations,
                 s.residual_evaluations, s.rhs_evaluations, s.jacobian_evaluations, o.method);
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
    } else if (a == "--tolerance" && i + 1 < argc) {
      o.tolerance = std::stod(argv[++i]);
    } else if (a == "--no-reference") {
      o.reference = false;
    } else {
      fmt::print(
          stderr,
          "usage: symdyn_bench_implicit_jacobians [--reps N] [--problem NAME]... [--tolerance TOL] "
          "[--no-reference]\n");
      return 2;
    }
  }
  try {
    for (const Problem& p : all_problems) {
      if (o.problems.empty() ||
          std::find(o.problems.begin(), o.problems.end(), p.name) != o.problems.end()) {
        measure(p, o);
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "symdyn_bench_implicit_jacobians: {}\n", e.what());
    return 1;
  }
  return 0;
}
