// The cost of closing loops at run time: MultibodySystem::accelerations() of
// the slider-crank with its dependent parameters in closed form and with its
// loop given implicitly (the same mechanics, docs/models.md), and of the
// four-bar, the double-wishbone quarter car and the Stewart platform, along a
// slow trajectory (each solve starts near the last one); and their Jacobians
// (M, C, K), exact and by differences.
#include <benchmark/benchmark.h>

#include "four_bar.hpp"
#include "quarter_car.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_implicit.hpp"
#include "stewart.hpp"
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

// One coordinate swept through `range` from its initial value in 1000 calls,
// the others at theirs.
template <class G>
void accelerations_about_initial(benchmark::State& state, int coordinate, double range) {
  MultibodySystem system(Model::from<G>());
  State s = system.initial_state();
  const double start = s.q(coordinate);
  Vector qdd, yd;
  int k = 0;
  for (auto _ : state) {
    s.q(coordinate) = start + range * (k++ % 1000) / 1000;
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
// The lower wishbone through 0.1 rad (6 cm of wheel travel).
void quarter_car_accelerations(benchmark::State& state) {
  accelerations_about_initial<symdyn_generated::quarter_car>(state, 1, 0.1);
}
BENCHMARK(quarter_car_accelerations);
// A leg through 1 cm.
void stewart_accelerations(benchmark::State& state) {
  accelerations_about_initial<symdyn_generated::stewart>(state, 0, 0.01);
}
BENCHMARK(stewart_accelerations);

// Its parts: the emitted loop equations with their Jacobians (one Newton
// iteration's evaluation), and the tree's M and h in the 24 extended
// coordinates, at the initial state.
void stewart_loop_equations(benchmark::State& state) {
  MultibodySystem system(Model::from<symdyn_generated::stewart>());
  const Model& model = system.model();
  const State x = system.extended_state(system.initial_state());
  const int n = model.nindependent(), m = model.ncon();
  Vector g(m), g_t(m);
  Matrix g_q(n, m), g_p(m, m);
  for (auto _ : state) {
    model.constraints(x.t, x.q.data(), g.data(), g_q.data(), g_p.data(), g_t.data());
    benchmark::DoNotOptimize(g_p.data());
  }
}
BENCHMARK(stewart_loop_equations);
void stewart_tree_equations(benchmark::State& state) {
  MultibodySystem system(Model::from<symdyn_generated::stewart>());
  const State x = system.extended_state(system.initial_state());
  Matrix M;
  Vector h;
  for (auto _ : state) {
    system.mass_matrix(x, M);
    system.bias_forces_emitted(x, h);
    benchmark::DoNotOptimize(h.data());
  }
}
BENCHMARK(stewart_tree_equations);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::slider_crank_dependent)->Arg(1)->Arg(0);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::slider_crank_implicit)->Arg(1)->Arg(0);
BENCHMARK_TEMPLATE(jacobians, symdyn_generated::four_bar)->Arg(1)->Arg(0);

}  // namespace

BENCHMARK_MAIN();
