// One run of a built-in scenario, as symdyn-sim runs it (force elements
// included), printed for bench/implicit/before_after.sh. It uses only what the
// scenario runner offered before the exact derivatives (commit 2dd6e1f) and still
// offers, so that the same source builds in both trees and measures both alike.
//
//   symdyn_bench_implicit_run <scenario> <t_end> <integrator> <tolerance>
//
// Output, one tab-separated line:
//   <cpu_ms> <steps> <rejected> <newton> <residuals> <rhs> <jacobians> <q_1 .. q_n> <qd_1 .. qd_n>
// cpu_ms: the process CPU time of the run alone (the scenario's set-up excluded);
// the final state with 17 significant digits. The output interval is the whole
// interval: nothing is written on the way.
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>

#include "run.hpp"
#include "scenario.hpp"

namespace {

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double positive(const char* text, const char* what) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0)) {
    std::fprintf(stderr, "error: %s '%s' is not a positive number\n", what, text);
    std::exit(2);
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s <scenario> <t_end> <integrator> <tolerance>\n", argv[0]);
    return 2;
  }
  symdyn::sim::RunOptions options;
  options.t_end = positive(argv[2], "t_end");
  options.integrator = argv[3];
  options.tolerance = positive(argv[4], "tolerance");
  options.output_interval = *options.t_end;
  try {
    symdyn::sim::Simulation simulation(symdyn::sim::find_builtin(argv[1]), options);
    const double start = cpu_ms();
    const symdyn::sim::RunResult r = simulation.run();
    const double cpu = cpu_ms() - start;
    const auto& st = r.statistics;
    std::printf("%.4f\t%ld\t%ld\t%ld\t%ld\t%ld\t%ld", cpu, st.steps, st.rejected_steps,
                st.newton_iterations, st.residual_evaluations, st.rhs_evaluations,
                st.jacobian_evaluations);
    for (const auto* v : {&r.final.q, &r.final.qd}) {
      for (Eigen::Index j = 0; j < v->size(); ++j) std::printf("\t%.17g", (*v)(j));
    }
    std::printf("\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
