// newmark and generalized-alpha against their previous implementation (newmark_baseline.cpp)
// in one run, on the double pendulum of docs/models.md released horizontal, over 1 s (the
// work-precision problem, ../work_precision/problems.hpp).
//
//   ./build/release/bench/symdyn_bench_newmark --benchmark_repetitions=5
//       --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
//   ./build/release/bench/symdyn_bench_newmark --count newmark tol 1e-8     # one run, for
//   callgrind
//
// Benchmarks <integrator>/tol=<tol> (rtol = atol), <integrator>/h=<h> (fixed step, default
// tolerances) and <integrator>/global=<tol> (fixed steps halved from 8e-3 until the global
// tolerance is met, the last two runs extrapolated), each also as <integrator>-baseline. Counters:
// error (largest |q - q_ref|, |qd - qd_ref| at 1 s against dop853 at 1e-13), steps, rejected,
// newton (iterations), jac (Jacobian evaluations).
//
// --count: the run alone inside counted_workload(), for
//   valgrind --tool=callgrind --toggle-collect='*counted_workload*' (instructions per run).

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "newmark_baseline.hpp"
#include "problems.hpp"
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn::runtime;

constexpr double kEnd = 1.0;
constexpr double kHalvingFrom = 8e-3;  // the first step of the global=<tolerance> runs

std::unique_ptr<Integrator> make(const std::string& name, const std::string& kind, double setting) {
  IntegratorOptions o;
  if (kind == "h") {
    o.fixed_step = true;
    o.initial_step = setting;
  } else if (kind == "global") {  // step halving from kHalvingFrom, extrapolated
    o.fixed_step = true;
    o.initial_step = kHalvingFrom;
    o.global_tolerance = setting;
  } else {
    o.relative_tolerance = o.absolute_tolerance = setting;
  }
  o.output_times = {kEnd};
  if (name == "newmark-baseline") return symdyn::bench::make_newmark_baseline(o);
  if (name == "generalized-alpha-baseline")
    return symdyn::bench::make_generalized_alpha_baseline(o);
  return make_integrator(name, o);
}

symdyn::bench::ProblemSystem& problem() {
  static symdyn::bench::ProblemSystem p = symdyn::bench::double_pendulum_problem();
  return p;
}

double error(const State& end) {
  static const State reference =
      make("dop853", "tol", 1e-13)->integrate(*problem().system, problem().initial, kEnd);
  return std::max((end.q - reference.q).cwiseAbs().maxCoeff(),
                  (end.qd - reference.qd).cwiseAbs().maxCoeff());
}

[[gnu::noinline]] State counted_workload(Integrator& integ) {
  return integ.integrate(*problem().system, problem().initial, kEnd);
}

void run(benchmark::State& bench, const std::string& name, const std::string& kind,
         double setting) {
  auto integ = make(name, kind, setting);
  State end;
  for (auto _ : bench) {
    end = integ->integrate(*problem().system, problem().initial, kEnd);
    benchmark::DoNotOptimize(end);
  }
  const Statistics& st = integ->statistics();
  bench.counters["error"] = error(end);
  bench.counters["steps"] = static_cast<double>(st.steps);
  bench.counters["rejected"] = static_cast<double>(st.rejected_steps);
  bench.counters["newton"] = static_cast<double>(st.newton_iterations);
  bench.counters["jac"] = static_cast<double>(st.jacobian_evaluations);
  if (kind == "global") bench.counters["estimate"] = st.global_error_estimate;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--count") {
    auto integ = make(argv[2], argv[3], std::stod(argv[4]));
    const State end = counted_workload(*integ);
    std::printf("%s %s=%s: error %.3e, %ld steps\n", argv[2], argv[3], argv[4], error(end),
                integ->statistics().steps);
    return 0;
  }
  struct Row {
    const char* name;
    const char* kind;
    std::vector<double> settings;
  };
  // Settings that reach the same errors: the baseline's error falls as tol^(2/3), today's as tol.
  const Row rows[] = {
      {"newmark", "tol", {1e-4, 1e-6, 3e-8, 1e-8, 1e-10}},
      {"newmark-baseline", "tol", {1e-6, 1e-8, 1e-10, 1e-11, 1e-12}},
      {"generalized-alpha", "tol", {1e-6, 1e-8}},
      {"generalized-alpha-baseline", "tol", {1e-10, 1e-12}},
      {"newmark", "h", {1e-3, 1e-4}},
      {"newmark-baseline", "h", {1e-3, 1e-4}},
      {"newmark", "global", {1e-4, 1e-6, 3e-8, 1e-9}},
      {"generalized-alpha", "global", {1e-6, 3e-8}},
  };
  for (const Row& r : rows) {
    for (double setting : r.settings) {
      const std::string label =
          fmt::format("double_pendulum_1s/{}/{}={:g}", r.name, r.kind, setting);
      const std::string name = r.name, kind = r.kind;
      benchmark::RegisterBenchmark(label.c_str(), [name, kind, setting](benchmark::State& s) {
        run(s, name, kind, setting);
      })->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
