// simplify on kinematics: the angular velocity of a ZYX rotation (entries of
// dR/dt R^T, derivatives by the chain rule written out below) and the
// position of a planar n-link chain. Counters: operation_cost before/after.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <array>
#include <map>
#include <vector>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/simplify.hpp>

namespace {

using namespace symdyn::symbolic;
using Mat3 = std::array<std::array<Expr, 3>, 3>;

Mat3 product(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Expr s = 0;
      for (int k = 0; k < 3; ++k) s = s + a[i][k] * b[k][j];
      c[i][j] = s;
    }
  }
  return c;
}

Mat3 rot_x(Expr q) {
  return {{{1, 0, 0}, {0, cos(q), -sin(q)}, {0, sin(q), cos(q)}}};
}
Mat3 rot_y(Expr q) {
  return {{{cos(q), 0, sin(q)}, {0, 1, 0}, {-sin(q), 0, cos(q)}}};
}
Mat3 rot_z(Expr q) {
  return {{{cos(q), -sin(q), 0}, {sin(q), cos(q), 0}, {0, 0, 1}}};
}

// d/dq of an expression built from sums, products, powers, sin and cos.
Expr d(Expr e, Expr q) {
  switch (e.kind()) {
    case Kind::Symbol:
      return e == q ? 1 : 0;
    case Kind::Add: {
      Expr s = 0;
      for (Expr a : e.args()) s = s + d(a, q);
      return s;
    }
    case Kind::Mul: {
      Expr s = 0;
      for (std::size_t i = 0; i < e.args().size(); ++i) {
        Expr t = d(e.arg(i), q);
        for (std::size_t j = 0; j < e.args().size(); ++j) {
          if (j != i) t = t * e.arg(j);
        }
        s = s + t;
      }
      return s;
    }
    case Kind::Pow:
      return e.arg(1) * pow(e.arg(0), Expr(e.arg(1).number() - Number(1))) * d(e.arg(0), q);
    case Kind::Sin:
      return cos(e.arg(0)) * d(e.arg(0), q);
    case Kind::Cos:
      return -sin(e.arg(0)) * d(e.arg(0), q);
    default:
      return 0;
  }
}

std::vector<Expr> zyx_angular_velocity() {
  const std::vector<Expr> q{symbol("q0", SymbolKind::Variable), symbol("q1", SymbolKind::Variable),
                            symbol("q2", SymbolKind::Variable)};
  const std::vector<Expr> qd{symbol("qd0", SymbolKind::Rate), symbol("qd1", SymbolKind::Rate),
                             symbol("qd2", SymbolKind::Rate)};
  const Mat3 r = product(product(rot_z(q[0]), rot_y(q[1])), rot_x(q[2]));
  Mat3 w;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Expr s = 0;
      for (int k = 0; k < 3; ++k) {
        Expr rdot = 0;
        for (std::size_t n = 0; n < q.size(); ++n) rdot = rdot + d(r[i][k], q[n]) * qd[n];
        s = s + rdot * r[j][k];
      }
      w[i][j] = s;
    }
  }
  return {w[2][1], w[0][2], w[1][0]};
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
