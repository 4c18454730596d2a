// simplify on kinematics: the angular velocity of a ZYX rotation (entries of
// dR/dt R^T, derivatives by the chain rule, tests/support/rotation_exprs.hpp) and the
// position of a planar n-link chain. Counters: operation_cost before/after.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <array>
#include <vector>

#include "support/rotation_exprs.hpp"
#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/simplify.hpp>

namespace {

using namespace symdyn::symbolic;
using namespace symdyn::testing::rotation_exprs;

std::vector<Expr> zyx_angular_velocity() {
  const std::vector<Expr> q{symbol("q0", SymbolKind::Variable), symbol("q1", SymbolKind::Variable),
                            symbol("q2", SymbolKind::Variable)};
  const std::vector<Expr> qd{symbol("qd0", SymbolKind::Rate), symbol("qd1", SymbolKind::Rate),
                             symbol("qd2", SymbolKind::Rate)};
  const std::array<Expr, 3> w =
      angular_velocity(product(product(rot_z(q[0]), rot_y(q[1])), rot_x(q[2])), q, qd);
  return {w.begin(), w.end()};
}

// Tip position (x, y) of a planar chain of n links, each rotation a 2x2 product.
std::vector<Expr> planar_chain(int n) {
  Expr c = 1, s = 0, x = 0, y = 0;
  for (int i = 0; i < n; ++i) {
    const Expr q = symbol(fmt::format("q{}", i), SymbolKind::Variable);
    const Expr l = symbol(fmt::format("l{}", i), SymbolKind::Parameter);
    const Expr c2 = c * cos(q) - s * sin(q);
    const Expr s2 = s * cos(q) + c * sin(q);
    c = expand(c2);
    s = expand(s2);
    x = x + l * c;
    y = y + l * s;
  }
  return {x, y};
}

void run(benchmark::State& state, std::vector<Expr> (*make)(int), int n) {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> outputs = make(n);
  std::vector<Expr> simplified;
  for (auto _ : state) {
    Simplifier simplifier;
    simplified = simplifier(outputs);
    benchmark::DoNotOptimize(simplified.data());
  }
  state.counters["cost_before"] = operation_cost(outputs);
  state.counters["cost_after"] = operation_cost(simplified);
}

void BM_ZyxAngularVelocity(benchmark::State& state) {
  run(
      state, [](int) { return zyx_angular_velocity(); }, 0);
}
BENCHMARK(BM_ZyxAngularVelocity)->Unit(benchmark::kMillisecond);

void BM_PlanarChainPosition(benchmark::State& state) {
  run(state, planar_chain, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_PlanarChainPosition)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
