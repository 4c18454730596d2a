// The cost of closing loops at run time: MultibodySystem::accelerations() of
// the slider-crank with its dependent parameters in closed form and with its
// loop given implicitly (the same mechanics, docs/models.md), and of the
// four-bar, along a slow trajectory (each solve starts near the last one);
// and their Jacobians (M, C, K), exact and by differences.
#include <benchmark/benchmark.h>

#include "four_bar.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_implicit.hpp"
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;

template <class G>
void accelerations(benchmark::State& state) {
  MultibodySystem system(Model::from<G>());
  State s = system.initial_state();
  Vector qdd, yd;
  int k = 0;
  for (auto _ : state) {
    s.q(0) = 1e-4 * (k++ % 100000);
    system.accelerations(s, qdd, yd);
    benchmark::DoNotOptimize(qdd.data());
  }
}

// M, C, K of the residual at the accelerations, along the same trajectory:
// exact (emitted derivatives, the loops' included) or central differences of
// the reduced residual (what loop models had before constraint_derivatives).
template <class G>
void jacobians(benchmark::State& state) {
  MultibodySystem system(Model::from<G>());
  system.set_exact_jacobians(state.range(0) != 0);
  State s = system.initial_state();
  Vector qdd, yd;
  Matrix M, C, K;
  int k = 0;
  for (auto _ : state) {
    s.q(0) = 1e-4 * (k++ % 100000);
    system.accelerations(s, qdd, yd);
    system.jacobians(s, qdd, M, C, K);
    benchmark::DoNotOptimize(K.data());
  }
  state.SetLabel(state.range(0) ? "exact" : "central differences");
}

BENCHMARK_TEMPLATE(accelerations, symdyn_generated::slider_crank_dependent);
BENCHMARK_TEMPLATE(accelerations, symdyn_generated::slider_crank_implicit);
BENCHMARK_TEMPLATE(accelerations, symdyn_generated::four_bar);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::slider_crank_dependent)->Arg(1)->Arg(0);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::slider_crank_implicit)->Arg(1)->Arg(0);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::four_bar)->Arg(1)->Arg(0);

}  // namespace

BENCHMARK_MAIN();
