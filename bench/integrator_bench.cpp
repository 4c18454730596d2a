// Run time against accuracy for every integrator on the nonlinear pendulum
// theta'' = -(g/L)·sin(theta), theta(0) = 1 rad, over 10 s, outputs every 0.1 s.
//
//   ./build/release/bench/symdyn_bench_integrators
//
// Counters: error = largest |theta - theta_ref| over the outputs (reference: RK4
// with h = 1e-4, error below 1e-13), drift = largest relative energy error,
// steps, rhs (accelerations calls), res (residual calls), jac (Jacobians).
// Adaptive methods run at relative = absolute tolerance 1e-4 ... 1e-10; rk4 at
// steps 1e-2 ... 3e-4.

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "runtime/test_systems.hpp"
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn::runtime;

constexpr double t_end = 10.0;
constexpr double interval = 0.1;

// g = 9.81, L = 1 (tests/runtime/test_systems.hpp).
using Pendulum = symdyn::runtime::testing::PendulumWithJacobians;

State initial() {
  State s;
  s.q = Vector::Constant(1, 1.0);
  s.qd = Vector::Zero(1);
  return s;
}

// theta at the output instants, from a fine RK4 run.
const std::vector<double>& reference() {
  static const std::vector<double> theta = [] {
    std::vector<double> out;
    IntegratorOptions o;
    o.initial_step = 1e-4;
    o.output_interval = interval;
    o.on_output = [&](const State& s, const Vector&, const Vector&) { out.push_back(s.q[0]); };
    Pendulum p;
    make_integrator("rk4", o)->integrate(p, initial(), t_end);
    return out;
  }();
  return theta;
}

void run(benchmark::State& bench, const std::string& name, double setting) {
  IntegratorOptions o;
  o.output_interval = interval;
  if (name == "rk4" || name == "midpoint") {
    o.initial_step = setting;
  } else {
    o.relative_tolerance = setting;
    o.absolute_tolerance = setting;
  }
  const auto& ref = reference();
  Pendulum p;
  const double e0 = p.energy(initial());
  double error = 0.0, drift = 0.0;
  std::size_t k = 0;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    error = std::max(error, std::abs(s.q[0] - ref[k++]));
    drift = std::max(drift, std::abs(p.energy(s) - e0) / std::abs(e0));
  };
  auto integ = make_integrator(name, o);
  for (auto _ : bench) {
    k = 0;
    error = drift = 0.0;
    benchmark::DoNotOptimize(integ->integrate(p, initial(), t_end));
  }
  const auto& st = integ->statistics();
  bench.counters["error"] = error;
  bench.counters["drift"] = drift;
  bench.counters["steps"] = static_cast<double>(st.steps);
  bench.counters["rhs"] = static_cast<double>(st.rhs_evaluations);
  bench.counters["res"] = static_cast<double>(st.residual_evaluations);
  bench.counters["jac"] = static_cast<double>(st.jacobian_evaluations);
}

}  // namespace

int main(int argc, char** argv) {
  for (const auto& name : integrator_names()) {
    const bool fixed = name == "rk4" || name == "midpoint";
    const std::vector<double> settings = fixed ? std::vector<double>{1e-2, 3e-3, 1e-3, 3e-4}
                                               : std::vector<double>{1e-4, 1e-6, 1e-8, 1e-10};
    for (double setting : settings) {
      const std::string label =
          fmt::format("pendulum/{}/{}={:g}", name, fixed ? "h" : "tol", setting);
      benchmark::RegisterBenchmark(label.c_str(), [name, setting](benchmark::State& s) {
        run(s, name, setting);
      })->Unit(benchmark::kMicrosecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
