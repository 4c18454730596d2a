// symdyn_bench_runtime: what the runtime adds to the emitted equations it calls.
//
// Per reference model, ways to get qdd at 64 random states (no force element,
// gravity only). What users call, on each of its two paths:
//   system              runtime::MultibodySystem::accelerations as constructed:
//                       the emitted forward_dynamics() where the generator
//                       chose it (--list says "recursive"), else M and h;
//   system_mass_matrix  the same after set_recursive(false): always M and h.
// The floors, the emitted code called by hand without the runtime's checks:
//   forward             the emitted forward_dynamics() (the articulated-body
//                       algorithm, tau = 0), the floor of the recursive path;
//                       only for models whose generated struct says
//                       has_forward_dynamics (otherwise refused, not registered);
//   dynamics            the emitted dynamics() (M and h in one call), then the
//                       runtime's own factorization (runtime::SpdSolver): the
//                       floor of the mass-matrix path;
//   equations           the emitted mass_matrix() and bias_forces(), then
//                       Eigen's dynamic-size LDLT: the solve a user would write.
//
//   symdyn_bench_runtime [Google Benchmark flags]     medians of CPU time (and
//       solve/*: SpdSolver against Eigen's LLT and LDLT by size)
//   symdyn_bench_runtime --count MODE MODEL [CALLS]   one workload, for
//       valgrind --tool=callgrind --toggle-collect='*counted_workload*'
//   symdyn_bench_runtime --list                       each model, its nq and the
//       system's default path (recursive or mass_matrix)
// bench/runtime_overhead.sh runs the instruction counts of every model.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "runtime_bench_models.hpp"
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace {

using namespace symdyn::runtime;

constexpr int kStates = 64;

// q within 0.1 of the model's initial configuration (dependent parameters
// stay in their domains), qd in [-1, 1].
std::vector<State> random_states(const Model& model) {
  std::mt19937 rng(2013);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<State> states;
  for (int k = 0; k < kStates; ++k) {
    State s = model.initial_state();
    for (int j = 0; j < model.nq(); ++j) {
      s.q(j) += 0.1 * u(rng);
      s.qd(j) = u(rng);
    }
    states.push_back(s);
  }
  return states;
}

// One way of computing qdd at a state, set up for a model.
using Workload = std::function<void(const State& s, Vector& qdd)>;

struct BenchModel {
  std::string name;
  std::function<Model()> make;
  bool recursive = false;  // the generator emitted forward_dynamics
  std::function<Workload()> equations;
  std::function<Workload()> dynamics;
  std::function<Workload()> forward;  // empty unless recursive
};

template <class G>
BenchModel bench_model(std::string name) {
  BenchModel b;
  b.name = std::move(name);
  b.make = [] { return Model::from<G>(); };
  b.equations = [] {
    auto M = std::make_shared<Matrix>(G::nq, G::nq);
    auto h = std::make_shared<Vector>(G::nq);
    auto ldlt = std::make_shared<Eigen::LDLT<Matrix>>(G::nq);
    return [=](const State& s, Vector& qdd) {
      G::mass_matrix(s.t, s.q.data(), G::param_defaults, M->data());
      G::bias_forces(s.t, s.q.data(), s.qd.data(), G::param_defaults, h->data());
      ldlt->compute(*M);
      qdd = ldlt->solve(-*h);
    };
  };
  b.dynamics = [] {
    auto M = std::make_shared<Matrix>(G::nq, G::nq);
    auto h = std::make_shared<Vector>(G::nq);
    auto solver = std::make_shared<SpdSolver>(G::nq);
    return [=](const State& s, Vector& qdd) {
      G::dynamics(s.t, s.q.data(), s.qd.data(), G::param_defaults, M->data(), h->data());
      if (!solver->factor(*M)) throw NumericError("singular mass matrix");
      qdd = -*h;
      solver->solve_in_place(qdd);
    };
  };
  if constexpr (requires { G::has_forward_dynamics; }) {
    if constexpr (G::has_forward_dynamics) {
      b.recursive = true;
      b.forward = [] {
        auto tau = std::make_shared<Vector>(Vector::Zero(G::nq));
        return [=](const State& s, Vector& qdd) {
          qdd.resize(G::nq);
          if (G::forward_dynamics(s.t, s.q.data(), s.qd.data(), tau->data(), G::param_defaults,
                                  qdd.data()) >= 0) {
            throw NumericError("singular articulated inertia");
          }
        };
      };
    }
  }
  return b;
}

const std::vector<BenchModel>& models() {
  static const std::vector<BenchModel> all = [] {
    std::vector<BenchModel> v;
#define SYMDYN_BENCH_MODEL(target) v.push_back(bench_model<symdyn_generated::target>(#target));
    SYMDYN_BENCH_MODELS(SYMDYN_BENCH_MODEL)
#undef SYMDYN_BENCH_MODEL
    return v;
  }();
  return all;
}

// The system's accelerations as a workload (the system lives in the closure):
// as constructed (its default path), or always M and h.
Workload system_workload(const BenchModel& b, bool mass_matrix_only) {
  auto system = std::make_shared<MultibodySystem>(b.make(), EquationsSource::emitted);
  if (mass_matrix_only) system->set_recursive(false);
  auto yd = std::make_shared<Vector>();
  return [=](const State& s, Vector& qdd) { system->accelerations(s, qdd, *yd); };
}

const char* const kModes = "system, system_mass_matrix, equations, dynamics, forward";

// The modes a model has: forward only where the generator emitted it.
std::vector<std::string> modes(const BenchModel& b) {
  std::vector<std::string> m = {"system", "system_mass_matrix", "equations", "dynamics"};
  if (b.recursive) m.emplace_back("forward");
  return m;
}

Workload workload(const BenchModel& b, const std::string& mode) {
  if (mode == "system") return system_workload(b, false);
  if (mode == "system_mass_matrix") return system_workload(b, true);
  if (mode == "equations") return b.equations();
  if (mode == "dynamics") return b.dynamics();
  if (mode == "forward") {
    if (!b.forward)
      throw std::invalid_argument(
          fmt::format("model '{}' has no emitted forward_dynamics", b.name));
    return b.forward();
  }
  throw std::invalid_argument(fmt::format("unknown mode '{}' ({})", mode, kModes));
}

// The counted region: callgrind --toggle-collect='*counted_workload*'.
[[gnu::noinline]] double counted_workload(const Workload& w, const std::vector<State>& states,
                                          int calls, Vector& qdd) {
  double sum = 0.0;
  for (int c = 0; c < calls; ++c) {
    w(states[static_cast<std::size_t>(c) % states.size()], qdd);
    sum += qdd(0);
  }
  return sum;
}

int count(const std::string& mode, const std::string& name, int calls) {
  for (const BenchModel& b : models()) {
    if (b.name != name) continue;
    const Workload w = workload(b, mode);
    const auto states = random_states(b.make());
    Vector qdd;
    for (const State& s : states) w(s, qdd);  // warm, outside the counted function
    const double sum = counted_workload(w, states, calls, qdd);
    fmt::print("{} {} calls {} checksum {:.17g}\n", mode, name, calls, sum);
    return 0;
  }
  fmt::print(stderr, "unknown model '{}' (--list)\n", name);
  return 2;
}

// A random SPD matrix of size n, as a mass matrix would be.
Matrix random_spd(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix A(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) A(i, j) = u(rng);
  }
  return A * A.transpose() + n * Matrix::Identity(n, n);
}

// Factor and solve: SpdSolver (its column loop up to kLoopUpTo, Eigen's LLT
// above) against Eigen's dynamic-size LLT and LDLT, where it switches.
void register_solver_benchmarks() {
  for (int n : {1, 2, 5, 13, 24, 32, 40, 48, 64}) {
    const Matrix M = random_spd(n);
    benchmark::RegisterBenchmark(fmt::format("solve/SpdSolver/{}", n).c_str(),
                                 [M, n](benchmark::State& st) {
                                   SpdSolver solver(n);
                                   Vector b(n);
                                   for (auto _ : st) {
                                     b.setOnes();
                                     if (!solver.factor(M)) st.SkipWithError("refused");
                                     solver.solve_in_place(b);
                                     benchmark::DoNotOptimize(b.data());
                                   }
                                 });
    benchmark::RegisterBenchmark(fmt::format("solve/EigenLLT/{}", n).c_str(),
                                 [M, n](benchmark::State& st) {
                                   Eigen::LLT<Matrix> llt(n);
                                   Vector b(n);
                                   for (auto _ : st) {
                                     b.setOnes();
                                     llt.compute(M);
                                     llt.solveInPlace(b);
                                     benchmark::DoNotOptimize(b.data());
                                   }
                                 });
    benchmark::RegisterBenchmark(fmt::format("solve/EigenLDLT/{}", n).c_str(),
                                 [M, n](benchmark::State& st) {
                                   Eigen::LDLT<Matrix> ldlt(n);
                                   Vector b(n);
                                   for (auto _ : st) {
                                     b.setOnes();
                                     ldlt.compute(M);
                                     ldlt.solveInPlace(b);
                                     benchmark::DoNotOptimize(b.data());
                                   }
                                 });
  }
}

void register_benchmarks() {
  for (const BenchModel& b : models()) {
    for (const std::string& mode : modes(b)) {
      benchmark::RegisterBenchmark(fmt::format("{}/{}", b.name, mode).c_str(),
                                   [&b, m = mode](benchmark::State& st) {
                                     const Workload w = workload(b, m);
                                     const auto states = random_states(b.make());
                                     Vector qdd;
                                     std::size_t k = 0;
                                     for (auto _ : st) {
                                       w(states[k++ % states.size()], qdd);
                                       benchmark::DoNotOptimize(qdd.data());
                                     }
                                   });
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "--list") {
    for (const BenchModel& b : models()) {
      fmt::print("{} {} {}\n", b.name, b.make().nq(), b.recursive ? "recursive" : "mass_matrix");
    }
    return 0;
  }
  if (!args.empty() && args[0] == "--count") {
    if (args.size() < 3) {
      fmt::print(stderr, "usage: symdyn_bench_runtime --count MODE MODEL [CALLS] (MODE: {})\n",
                 kModes);
      return 2;
    }
    try {
      return count(args[1], args[2], args.size() > 3 ? std::stoi(args[3]) : 1000);
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "{}\n", e.what());
      return 2;
    }
  }
  register_benchmarks();
  register_solver_benchmarks();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
