// Kinematics of chain_N (absolute variant, docs/models.md):
// poses of all bodies as products of 4x4 matrices, then their velocities and
// accelerations by the total time derivative. symdyn beside GiNaC on the same
// task. See bench/README.md for how to run and what the counters mean.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "support/chain_model.hpp"
#include "support/dag_size.hpp"
#include <symdyn/symbolic/diff.hpp>

#ifdef SYMDYN_HAVE_GINAC
#include <ginac/ginac.h>
#endif

namespace {

using symdyn::testing::append_pose_entries;
using symdyn::testing::chain_absolute;

// ---------------------------------------------------------------------------
// symdyn: q_i, qd_i, qdd_i are symbols; one TimeDerivative (q_i -> qd_i,
// qd_i -> qdd_i) takes positions to velocities, then velocities to
// accelerations, sharing its memo between the two.

struct SymdynKinematics {
  std::vector<symdyn::symbolic::Expr> positions, velocities, accelerations;  // 12 entries per body
};

SymdynKinematics symdyn_kinematics(int n) {
  using namespace symdyn::symbolic;
  std::vector<Expr> q;
  RateMap rates;
  for (int i = 0; i < n; ++i) {
    q.push_back(symbol(fmt::format("q{}", i), SymbolKind::Variable));
    const Expr qd = symbol(fmt::format("qd{}", i), SymbolKind::Rate);
    rates.emplace(q.back(), qd);
    rates.emplace(qd, symbol(fmt::format("qdd{}", i), SymbolKind::Acceleration));
  }
  SymdynKinematics k;
  for (const auto& pose : chain_absolute<Expr>(q, rational(1, 4)))
    append_pose_entries(pose, k.positions);
  TimeDerivative dt(std::move(rates));
  for (Expr e : k.positions) k.velocities.push_back(dt(e));
  for (Expr e : k.velocities) k.accelerations.push_back(dt(e));
  return k;
}

void BM_symdyn_chain(benchmark::State& state) {
  using namespace symdyn::symbolic;
  const int n = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Context context;  // a fresh one per iteration: nothing is reused
    Context::Scope scope(context);
    const SymdynKinematics k = symdyn_kinematics(n);
    benchmark::DoNotOptimize(k.accelerations.back().node());
  }
  // Sizes from one more run, outside the timed loop.
  Context context;
  Context::Scope scope(context);
  const SymdynKinematics k = symdyn_kinematics(n);
  std::vector<Expr> all = k.positions;
  all.insert(all.end(), k.velocities.begin(), k.velocities.end());
  all.insert(all.end(), k.accelerations.begin(), k.accelerations.end());
  state.counters["position_nodes"] =
      static_cast<double>(symdyn::testing::count_dag_nodes(k.positions));
  state.counters["dag_nodes"] = static_cast<double>(symdyn::testing::count_dag_nodes(all));
  state.counters["context_nodes"] = static_cast<double>(context.size());
  state.counters["bytes_per_node"] =
      static_cast<double>(context.memory_bytes()) / static_cast<double>(context.size());
}

#ifdef SYMDYN_HAVE_GINAC
// ---------------------------------------------------------------------------
// GiNaC: q_i is the function q(i, t) of time, whose derivative is qd(i, t),
// whose derivative is qdd(i, t); velocities and accelerations are GiNaC's
// diff with respect to t, one call per entry. This is the fair equivalent of
// one total-time-derivative sweep: a single differentiation per expression
// (a chain rule over the q_i and qd_i would differentiate each entry 2N times).

DECLARE_FUNCTION_2P(chain_q)
DECLARE_FUNCTION_2P(chain_qd)
DECLARE_FUNCTION_2P(chain_qdd)

GiNaC::ex chain_q_deriv(const GiNaC::ex& i, const GiNaC::ex& t, unsigned /*param*/) {
  return chain_qd(i, t);
}
GiNaC::ex chain_qd_deriv(const GiNaC::ex& i, const GiNaC::ex& t, unsigned /*param*/) {
  return chain_qdd(i, t);
}

REGISTER_FUNCTION(chain_q, derivative_func(chain_q_deriv))
REGISTER_FUNCTION(chain_qd, derivative_func(chain_qd_deriv))
REGISTER_FUNCTION(chain_qdd, dummy())

struct GinacKinematics {
  std::vector<GiNaC::ex> positions, velocities, accelerations;
};

GinacKinematics ginac_kinematics(int n, const GiNaC::symbol& t) {
  std::vector<GiNaC::ex> q;
  for (int i = 0; i < n; ++i) q.push_back(chain_q(i, t));
  GinacKinematics k;
  for (const auto& pose : chain_absolute<GiNaC::ex>(q, GiNaC::ex(1) / 4))
    append_pose_entries(pose, k.positions);
  for (const GiNaC::ex& e : k.positions) k.velocities.push_back(e.diff(t));
  for (const GiNaC::ex& e : k.velocities) k.accelerations.push_back(e.diff(t));
  return k;
}

// GiNaC shares subtrees by reference counting but does not intern them. Two
// sizes: distinct subexpressions (structural equality: what an interning
// engine would store) and the size as a tree (what GiNaC's diff traverses).
struct GinacSizes {
  double distinct = 0;
  double tree = 0;
};

GinacSizes ginac_sizes(const std::vector<GiNaC::ex>& outputs) {
  std::unordered_map<GiNaC::ex, double, std::hash<GiNaC::ex>, GiNaC::ex_is_equal> tree_size;
  // Post-order with an explicit stack: a node is sized once its operands are.
  auto size_of = [&](const GiNaC::ex& root) {
    std::vector<std::pair<GiNaC::ex, bool>> stack{{root, false}};
    while (!stack.empty()) {
      auto [e, expanded] = stack.back();
      stack.pop_back();
      if (tree_size.count(e) != 0) continue;
      if (!expanded) {
        stack.emplace_back(e, true);
        for (std::size_t i = 0; i < e.nops(); ++i) stack.emplace_back(e.op(i), false);
        continue;
      }
      double size = 1;
      for (std::size_t i = 0; i < e.nops(); ++i) size += tree_size.at(e.op(i));
      tree_size.emplace(e, size);
    }
    return tree_size.at(root);
  };
  GinacSizes sizes;
  for (const GiNaC::ex& e : outputs) sizes.tree += size_of(e);
  sizes.distinct = static_cast<double>(tree_size.size());
  return sizes;
}

void BM_ginac_chain(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const GiNaC::symbol t("t");
  for (auto _ : state) {
    const GinacKinematics k = ginac_kinematics(n, t);
    benchmark::DoNotOptimize(&k.accelerations.back());
  }
  const GinacKinematics k = ginac_kinematics(n, t);
  std::vector<GiNaC::ex> all = k.positions;
  all.insert(all.end(), k.velocities.begin(), k.velocities.end());
  all.insert(all.end(), k.accelerations.begin(), k.accelerations.end());
  const GinacSizes positions = ginac_sizes(k.positions);
  const GinacSizes sizes = ginac_sizes(all);
  state.counters["position_nodes"] = positions.distinct;
  state.counters["dag_nodes"] = sizes.distinct;
  state.counters["tree_nodes"] = sizes.tree;
}
#endif

// --ginac_max_n=<N> (default 12): the largest chain GiNaC is run on, among
// 2, 4, 8, 12, 16. GiNaC's time grows exponentially with N (about a minute at
// N = 16), so it runs one iteration per size from N = 8 on.
int take_ginac_max_n(int* argc, char** argv) {
  int max_n = 12;
  constexpr const char* kFlag = "--ginac_max_n=";
  int kept = 1;
  for (int i = 1; i < *argc; ++i) {
    if (std::strncmp(argv[i], kFlag, std::strlen(kFlag)) == 0) {
      max_n = std::atoi(argv[i] + std::strlen(kFlag));
    } else {
      argv[kept++] = argv[i];
    }
  }
  *argc = kept;
  return max_n;
}

void register_benchmarks(int ginac_max_n) {
  auto* symdyn =
      benchmark::RegisterBenchmark("symdyn_chain", BM_symdyn_chain)->Unit(benchmark::kMillisecond);
  for (int n : {2, 4, 8, 12, 16, 32, 64}) symdyn->Arg(n);
#ifdef SYMDYN_HAVE_GINAC
  for (int n : {2, 4, 8, 12, 16}) {
    if (n > ginac_max_n) break;
    auto* ginac = benchmark::RegisterBenchmark("ginac_chain", BM_ginac_chain)
                      ->Unit(benchmark::kMillisecond)
                      ->Arg(n);
    if (n >= 8) ginac->Iterations(1);
  }
#else
  (void)ginac_max_n;
#endif
}

}  // namespace

int main(int argc, char** argv) {
  register_benchmarks(take_ginac_max_n(&argc, argv));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
