// The program interpreter against direct DAG evaluation (eval.hpp) on random
// expressions of a few thousand nodes, and the cost of compiling them.
//   build/release/bench/symdyn_bench_program
// Counters: dag_nodes (distinct nodes the outputs need), instructions,
// operations (OperationCount::total), weighted (OperationCount::weighted).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <map>
#include <memory>
#include <unordered_set>

#include "support/random_expr.hpp"
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/program.hpp>

namespace {

using namespace symdyn::symbolic;

// Adds the nodes e needs to `seen`; returns how many were new.
std::size_t visit(Expr e, std::unordered_set<std::uint32_t>& seen) {
  std::size_t added = 0;
  std::vector<Expr> stack{e};
  while (!stack.empty()) {
    const Expr top = stack.back();
    stack.pop_back();
    if (!seen.insert(top.id()).second) continue;
    ++added;
    for (Expr a : top.args()) stack.push_back(a);
  }
  return added;
}

// Random outputs over six symbols, added until they need `target` DAG nodes.
struct Fixture {
  explicit Fixture(std::size_t target) {
    Context::Scope scope(context);
    for (int i = 0; i < 6; ++i) inputs.push_back(symbol(fmt::format("x{}", i)));
    symdyn::testing::RandomExpr gen(12345, inputs);
    std::unordered_set<std::uint32_t> seen;
    while (dag_nodes < target) {
      outputs.push_back(gen(7));
      dag_nodes += visit(outputs.back(), seen);
    }
    program = compile_program(inputs, outputs);
    point = gen.point();
    for (std::size_t i = 0; i < inputs.size(); ++i) bindings[inputs[i]] = point[i];
  }
  Context context;
  std::vector<Expr> inputs;
  std::vector<Expr> outputs;
  std::size_t dag_nodes = 0;
  Program program;
  std::vector<double> point;
  Bindings<double> bindings;
};

const Fixture& fixture(std::size_t target) {
  static std::map<std::size_t, std::unique_ptr<Fixture>> fixtures;
  auto& f = fixtures[target];
  if (!f) f = std::make_unique<Fixture>(target);
  return *f;
}

void set_counters(benchmark::State& state, const Fixture& f) {
  const OperationCount count = f.program.operation_count();
  state.counters["dag_nodes"] = static_cast<double>(f.dag_nodes);
  state.counters["outputs"] = static_cast<double>(f.outputs.size());
  state.counters["instructions"] = static_cast<double>(f.program.instructions().size());
  state.counters["operations"] = count.total();
  state.counters["weighted"] = count.weighted();
}

void BM_Interpreter(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<std::size_t>(state.range(0)));
  std::vector<double> out(f.program.output_count());
  std::vector<double> work(f.program.workspace_size());
  for (auto _ : state) {
    f.program.run<double>(f.point, out, work);
    benchmark::DoNotOptimize(out.data());
  }
  set_counters(state, f);
}

void BM_InterpreterComplex(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<std::size_t>(state.range(0)));
  std::vector<std::complex<double>> in(f.point.begin(), f.point.end());
  in[0] += std::complex<double>(0, 1e-20);
  std::vector<std::complex<double>> out(f.program.output_count());
  std::vector<std::complex<double>> work(f.program.workspace_size());
  for (auto _ : state) {
    f.program.run<std::complex<double>>(in, out, work);
    benchmark::DoNotOptimize(out.data());
  }
  set_counters(state, f);
}

// The baseline: every output through one memoized Evaluator.
void BM_DagEvaluate(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    Evaluator<double> eval(f.bindings);
    double sum = 0.0;
    for (Expr e : f.outputs) sum += eval(e);
    benchmark::DoNotOptimize(sum);
  }
  set_counters(state, f);
}

void BM_Compile(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    Program p = compile_program(f.inputs, f.outputs);
    benchmark::DoNotOptimize(p.instructions().data());
  }
  set_counters(state, f);
}

BENCHMARK(BM_Interpreter)->Arg(1000)->Arg(4000)->Arg(16000);
BENCHMARK(BM_InterpreterComplex)->Arg(1000)->Arg(4000)->Arg(16000);
BENCHMARK(BM_DagEvaluate)->Arg(1000)->Arg(4000)->Arg(16000);
BENCHMARK(BM_Compile)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
