// The cost of closing loops at run time: MultibodySystem::accelerations() of
// the slider-crank with its dependent parameters in closed form and with its
// loop given implicitly (the same mechanics, docs/models.md), and of the
// four-bar, along a slow trajectory (each solve starts near the last one).
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

BENCHMARK_TEMPLATE(accelerations, symdyn_generated::slider_crank_dependent);
BENCHMARK_TEMPLATE(accelerations, symdyn_generated::slider_crank_implicit);
BENCHMARK_TEMPLATE(accelerations, symdyn_generated::four_bar);

}  // namespace

BENCHMARK_MAIN();
