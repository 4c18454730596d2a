#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <regex>
#include <set>
#include <sstream>

#include "support/random_expr.hpp"
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/program.hpp>

using namespace symdyn::symbolic;
using Complex = std::complex<double>;

namespace {

// |a - b| within tol relative to the larger magnitude, with an absolute floor of tol.
template <class T>
bool close(T a, T b, T tol) {
  using std::abs;
  return abs(a - b) <= tol * std::max({T(1), abs(a), abs(b)});
}

std::vector<double> run(const Program& p, std::vector<double> in) {
  return p.evaluate<double>(in);
}

// The program's values at `point` against the DAG's, and its derivative in
// input `step` by complex step against the DAG's.
void check_values(const Program& program, const std::vector<Expr>& xs,
                  const std::vector<Expr>& outputs, const std::vector<double>& point,
                  std::size_t step) {
  Bindings<double> at;
  Bindings<Complex> at_z;
  std::vector<Complex> zpoint(point.begin(), point.end());
  zpoint[step] += Complex(0, 1e-20);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    at[xs[i]] = point[i];
    at_z[xs[i]] = zpoint[i];
  }
  const std::vector<double> got = run(program, point);
  const std::vector<Complex> got_z = program.evaluate<Complex>(zpoint);
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    INFO("output " << k << ": " << outputs[k]);
    CHECK(close(got[k], evaluate(outputs[k], at), 1e-12));
    CHECK(close(got_z[k].imag() * 1e20, evaluate(outputs[k], at_z).imag() * 1e20, 1e-11));
  }
}

int count_opcode(const Program& p, Opcode op) {
  const auto code = p.instructions();
  return static_cast<int>(
      std::count_if(code.begin(), code.end(), [op](const Instruction& i) { return i.op == op; }));
}

OperationCount count_of(std::vector<Expr> inputs, std::vector<Expr> outputs) {
  return compile_program(inputs, outputs).operation_count();
}

OperationCount ops(int add, int mul, int div, int neg) {
  OperationCount c;
  c.add = add;
  c.mul = mul;
  c.div = div;
  c.neg = neg;
  return c;
}

}  // namespace

TEST_CASE("program equals direct DAG evaluation on random expressions", "[program]") {
  constexpr unsigned kSeeds = 1000;
  constexpr int kOutputs = 4;  // 4000 expressions
  for (unsigned seed = 0; seed < kSeeds; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
    symdyn::testing::RandomExpr gen(seed, xs);
    std::vector<Expr> outputs;
    for (int k = 0; k < kOutputs; ++k) outputs.push_back(gen(4 + static_cast<int>(gen.pick(2))));
    const Program program = compile_program(xs, outputs);
    const std::vector<double> point = gen.point();
    INFO("seed " << seed << "\n" << to_string(program));

    // double
    Bindings<double> at;
    for (std::size_t i = 0; i < xs.size(); ++i) at[xs[i]] = point[i];
    const std::vector<double> got = run(program, point);
    for (int k = 0; k < kOutputs; ++k) {
      const double want = evaluate(outputs[k], at);
      INFO("output " << k << ": " << outputs[k] << " = " << want << ", program gives " << got[k]);
      CHECK(close(got[k], want, 1e-11));
    }

    // long double
    Bindings<long double> at_long;
    std::vector<long double> point_long(point.begin(), point.end());
    for (std::size_t i = 0; i < xs.size(); ++i) at_long[xs[i]] = point_long[i];
    const std::vector<long double> got_long = program.evaluate<long double>(point_long);
    for (int k = 0; k < kOutputs; ++k) {
      CHECK(close(got_long[k], evaluate(outputs[k], at_long), 1e-14L));
    }

    // complex step: d/dv of every output, for one input v
    const std::size_t v = seed % xs.size();
    const double h = 1e-20;
    std::vector<Complex> zpoint(point.begin(), point.end());
    zpoint[v] += Complex(0, h);
    Bindings<Complex> at_z;
    for (std::size_t i = 0; i < xs.size(); ++i) at_z[xs[i]] = zpoint[i];
    const std::vector<Complex> got_z = program.evaluate<Complex>(zpoint);
    for (int k = 0; k < kOutputs; ++k) {
      const Complex want = evaluate(outputs[k], at_z);
      INFO("d/d" << xs[v] << " of output " << k << ": " << want.imag() / h << ", program gives "
                 << got_z[k].imag() / h);
      CHECK(close(got_z[k].real(), want.real(), 1e-11));
      CHECK(close(got_z[k].imag() / h, want.imag() / h, 1e-9));
    }

    // Same outputs, same program, byte for byte.
    CHECK(to_string(compile_program(xs, outputs)) == to_string(program));

    // Output order does not change the work; repeated outputs cost nothing.
    std::vector<Expr> reversed(outputs.rbegin(), outputs.rend());
    const Program program_reversed = compile_program(xs, reversed);
    CHECK(program_reversed.operation_count() == program.operation_count());
    const std::vector<double> got_reversed = run(program_reversed, point);
    for (int k = 0; k < kOutputs; ++k) CHECK(got_reversed[kOutputs - 1 - k] == got[k]);
    std::vector<Expr> repeated = outputs;
    repeated.push_back(outputs[1]);
    repeated.insert(repeated.begin(), outputs[2]);
    CHECK(compile_program(xs, repeated).operation_count() == program.operation_count());
  }
}

// Wide sums of signed, scaled products and quotients over few symbols: many
// shared operand pairs, so pair CSE and reciprocal sharing do most of the work.
TEST_CASE("program equals DAG evaluation on wide sums and products with shared pairs",
          "[program]") {
  for (unsigned seed = 0; seed < 300; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    std::vector<Expr> xs;
    for (int i = 0; i < 6; ++i) xs.push_back(symbol(fmt::format("s{}", i)));
    symdyn::testing::RandomExpr gen(seed, xs);
    const std::vector<Expr> coefficients{Expr(1), Expr(-1), Expr(2), rational(-3, 2)};
    std::vector<Expr> outputs;
    for (int k = 0; k < 6; ++k) {
      std::vector<Expr> terms;
      const std::size_t n = 3 + gen.pick(10);
      for (std::size_t t = 0; t < n; ++t) {
        const Expr c = coefficients[gen.pick(coefficients.size())];
        const Expr a = xs[gen.pick(xs.size())];
        const Expr b = xs[gen.pick(xs.size())];
        const Expr d = xs[gen.pick(xs.size())];
        switch (gen.pick(3)) {
          case 0:
            terms.push_back(c * a * b * d);
            break;
          case 1:
            terms.push_back(c * a / (b * b + 1));
            break;
          default:
            terms.push_back(c * a);
            break;
        }
      }
      outputs.push_back(add(terms));
    }
    const Program program = compile_program(xs, outputs);
    const std::vector<double> point = gen.point();
    INFO("seed " << seed << "\n" << to_string(program));
    check_values(program, xs, outputs, point, seed % xs.size());
    std::vector<Expr> rotated(outputs.begin() + 2, outputs.end());
    rotated.insert(rotated.end(), outputs.begin(), outputs.begin() + 2);
    CHECK(compile_program(xs, rotated).operation_count() == program.operation_count());
  }
}

TEST_CASE("a sum too wide for pair CSE is still computed right", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  std::vector<Expr> xs;
  for (int i = 0; i < 20; ++i) xs.push_back(symbol(fmt::format("s{}", i)));
  std::vector<Expr> terms;
  for (int i = 0; i < 20; ++i) {
    for (int j = i + 1; j < 20; ++j)
      terms.push_back((i + j) % 3 == 0 ? -xs[i] * xs[j] : xs[i] * xs[j]);
  }
  const Expr wide = add(terms);  // 190 terms
  REQUIRE(wide.args().size() > 128);
  const Program p = compile_program(xs, std::vector{wide, xs[0] * xs[1] + xs[2]});
  std::vector<double> point;
  Bindings<double> at;
  for (int i = 0; i < 20; ++i) {
    point.push_back(0.1 * i - 0.7);
    at[xs[i]] = point.back();
  }
  const auto out = run(p, point);
  CHECK(close(out[0], evaluate(wide, at), 1e-13));
  CHECK(out[1] == point[0] * point[1] + point[2]);
  // 190 products, 189 additions, s0·s1 once.
  CHECK(p.operation_count() == ops(190, 190, 0, 0));
}

TEST_CASE("every instruction is scheduled before use and defines fresh slots", "[program]") {
  for (unsigned seed = 0; seed < 200; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
    symdyn::testing::RandomExpr gen(seed, xs);
    const std::vector<Expr> outputs{gen(5), gen(5), gen(5)};
    const Program program = compile_program(xs, outputs);
    std::vector<int> defined(program.slot_count(), 0);
    std::vector<int> used(program.slot_count(), 0);
    std::uint32_t next = 0;
    for (const Instruction& ins : program.instructions()) {
      for (int a = 0; a < info(ins.op).arity; ++a) {
        REQUIRE(defined[ins.args[a]] == 1);
        ++used[ins.args[a]];
      }
      for (int r = 0; r < info(ins.op).results; ++r) {
        REQUIRE(ins.results[r] == next++);  // numbered in schedule order
        ++defined[ins.results[r]];
      }
    }
    for (std::uint32_t s : program.output_slots()) ++used[s];
    CHECK(next == program.slot_count());
    // No dead code: every slot is read by an instruction or is an output.
    CHECK(std::count(used.begin(), used.end(), 0) == 0);
  }
}

TEST_CASE("sin and cos of one argument are one sincos", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  const Program p =
      compile_program(std::vector{x, y}, std::vector{sin(x + y) * y, cos(x + y) - y, sin(y)});
  const OperationCount c = p.operation_count();
  CHECK(c.sincos == 1);
  CHECK(c.call(Kind::Sin) == 1);  // sin(y): no cos(y), no fusion
  CHECK(c.call(Kind::Cos) == 0);
  CHECK(count_opcode(p, Opcode::SinCos) == 1);
  const auto out = run(p, {0.3, -1.1});
  CHECK(out[0] == Approx(std::sin(0.3 - 1.1) * -1.1).epsilon(1e-15));
  CHECK(out[1] == Approx(std::cos(0.3 - 1.1) + 1.1).epsilon(1e-15));
  CHECK(out[2] == Approx(std::sin(-1.1)).epsilon(1e-15));
}

TEST_CASE("dead code is never scheduled and unused inputs are never read", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");
  const Expr unused = exp(z) + sin(x) * cos(y);  // built, but no output needs it
  (void)unused;
  const Program p = compile_program(std::vector{x, y, z}, std::vector{x * y});
  CHECK(p.operation_count() == ops(0, 1, 0, 0));
  CHECK(p.instructions().size() == 3);  // two inputs, one mul
  for (const Instruction& ins : p.instructions())
    CHECK(!(ins.op == Opcode::Input && ins.input == 2));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(run(p, {2.0, 3.0, nan})[0] == 6.0);
}

TEST_CASE("pair CSE computes operand pairs shared by sums and products once", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a"), b = symbol("b"), c = symbol("c"), d = symbol("d");
  const std::vector<Expr> in{a, b, c, d};
  // a + b once, then + c and + d: 3 adds instead of 4.
  CHECK(count_of(in, {a + b + c, a + b + d}) == ops(3, 0, 0, 0));
  CHECK(count_of(in, {a * b * c, a * b * d}) == ops(0, 3, 0, 0));
  // a - b shared with its negation b - a: (a - b) + c and d - (a - b).
  CHECK(count_of(in, {a - b + c, b - a + d}) == ops(3, 0, 0, 0));
  // a + b + c once, then + d; the product uses the sum node itself.
  CHECK(count_of(in, {a + b + c, a + b + c + d, (a + b + c) * d}) == ops(3, 1, 0, 0));
  // Products: a·b shared by three, then a·b·c by two.
  CHECK(count_of(in, {a * b * c, a * b * c * d, a * b * d}) == ops(0, 4, 0, 0));
  // Nothing shared: no change from plain binarization.
  CHECK(count_of(in, {a + b, c + d}) == ops(2, 0, 0, 0));
  const Program p = compile_program(in, std::vector{a - b + c, b - a + d});
  const auto out = run(p, {1.5, 0.25, -3.0, 7.0});
  CHECK(out[0] == 1.5 - 0.25 - 3.0);
  CHECK(out[1] == 0.25 - 1.5 + 7.0);
}

TEST_CASE(
    "pair CSE extracts first a pair computed for itself, where that makes no output group longer",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a"), b = symbol("b"), c = symbol("c"), d = symbol("d"), e = symbol("e");
  const std::vector<Expr> in{a, b, c, d, e};
  // A rotation's products: a·d beside a·b·d makes the latter (a·d)·b, one
  // multiplication each, where a·b shared by a·b·c and a·b·d costs 3 for two.
  const std::vector<Expr> outputs{a * b * c, a * b * d, e * b * c, e * b * d,
                                  a * d,     e * c,     e * d,     a * c};
  const std::vector<Expr> triples(outputs.begin(), outputs.begin() + 4);
  CHECK(count_of(in, outputs) == ops(0, 8, 0, 0));
  CHECK(count_of(in, triples) == ops(0, 6, 0, 0));  // a·b and e·b shared
  // Groups of outputs computed together: the products alone would need the
  // pairs that the other group computes, 8 multiplications instead of 6, so
  // the other order is kept.
  const std::vector<std::vector<std::size_t>> triples_apart{{0, 1, 2, 3}, {0, 1, 2, 3, 4, 5, 6, 7}};
  const std::vector<std::vector<std::size_t>> pairs_apart{{4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7}};
  const Program kept = compile_program(in, outputs, {}, triples_apart);
  CHECK(kept.operation_count() == ops(0, 10, 0, 0));
  CHECK(kept.subprogram(triples_apart[0], std::vector<std::size_t>{0, 1, 2, 3, 4})
            .operation_count() == ops(0, 6, 0, 0));
  CHECK(compile_program(in, outputs, {}, pairs_apart).operation_count() == ops(0, 8, 0, 0));
  const std::vector<double> point{0.3, -1.1, 0.7, 2.2, -0.4};
  Bindings<double> at;
  for (std::size_t i = 0; i < in.size(); ++i) at[in[i]] = point[i];
  for (const Program& p : {compile_program(in, outputs), kept}) {
    const auto out = run(p, point);
    for (std::size_t k = 0; k < outputs.size(); ++k)
      CHECK(close(out[k], evaluate(outputs[k], at), 1e-15));
  }
  CHECK_THROWS_WITH(compile_program(in, outputs, {}, std::vector<std::vector<std::size_t>>{{8}}),
                    "compile_program: a group names output 8 of 8");
}

TEST_CASE("negations and divisions fold into subtractions and divisions", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");
  const std::vector<Expr> in{x, y, z};
  CHECK(count_of(in, {x - y}) == ops(1, 0, 0, 0));
  CHECK(count_of(in, {x / y}) == ops(0, 0, 1, 0));
  CHECK(count_of(in, {-x}) == ops(0, 0, 0, 1));
  CHECK(count_of(in, {-(x * y)}) == ops(0, 1, 0, 1));
  CHECK(count_of(in, {x - 2 * y}) == ops(1, 1, 0, 0));
  CHECK(count_of(in, {z - x * y}) == ops(1, 1, 0, 0));
  CHECK(count_of(in, {-x - y}) == ops(1, 0, 0, 1));        // -(x + y)
  CHECK(count_of(in, {z * (-x - y)}) == ops(1, 1, 0, 1));  // -(z·(x + y))
  CHECK(count_of(in, {z + (-x) * y}) == ops(1, 1, 0, 0));  // z - x·y
  CHECK(count_of(in, {x / (y * z)}) == ops(0, 1, 1, 0));   // one division by y·z
  CHECK(count_of(in, {-x / y}) == ops(0, 0, 1, 1));
  CHECK(count_of(in, {z - x / y}) == ops(1, 0, 1, 0));
  CHECK(count_of(in, {Expr(3) - x}) == ops(1, 0, 0, 0));
  // Two divisions by y: 1/y once and two multiplications.
  CHECK(count_of(in, {x / y, z / y}) == ops(0, 2, 1, 0));
  CHECK(count_of(in, {x / y, pow(y, -1)}) == ops(0, 1, 1, 0));
  const auto out =
      run(compile_program(in, std::vector{-x / y, z - x / y, x / y, z / y}), {3.0, 4.0, 5.0});
  CHECK(out[0] == -0.75);
  CHECK(out[1] == 5.0 - 0.75);
  CHECK(out[2] == 0.75);
  CHECK(out[3] == 1.25);
}

TEST_CASE(
    "a negation left at an output is absorbed by the code of its operand when nothing else reads "
    "it",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z"), w = symbol("w");
  const std::vector<Expr> in{x, y, z, w};
  struct Case {
    std::vector<Expr> outputs;
    OperationCount count;
  };
  const Case cases[] = {
      // -(x·y + z) = (-x)·y - z with -x an output: the neg of the sum is saved.
      {{-x, -(x * y + z)}, ops(1, 1, 0, 1)},
      {{-y, -(x * y + z * w)}, ops(1, 2, 0, 1)},
      {{-x, -(x / y + z)}, ops(1, 0, 1, 1)},
      // Two levels down: -(w·(x·y + z) + w) = w·((-x)·y - z) - w.
      {{-x, -(w + (x * y + z) * w)}, ops(2, 2, 0, 1)},
      // The sum, or the product in it, is read elsewhere: rewriting it would
      // cost what the neg does.
      {{-x, -(x * y + z), x * y + z}, ops(1, 1, 0, 2)},
      {{-x, -(x * y + z), x * y}, ops(1, 1, 0, 2)},
      // No operand's negation at hand: the neg stays.
      {{-(x * y + z)}, ops(1, 1, 0, 1)},
  };
  const std::vector<double> point{0.7, -1.3, 2.1, 0.4};
  Bindings<double> at;
  for (std::size_t i = 0; i < in.size(); ++i) at[in[i]] = point[i];
  for (const Case& c : cases) {
    const Program p = compile_program(in, c.outputs);
    INFO(to_string(p));
    CHECK(p.operation_count() == c.count);
    const auto out = run(p, point);
    for (std::size_t k = 0; k < c.outputs.size(); ++k)
      CHECK(close(out[k], evaluate(c.outputs[k], at), 1e-15));
  }
}

TEST_CASE("absorbed negations keep every value: random sums, their negations and negated operands",
          "[program]") {
  for (unsigned seed = 0; seed < 300; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    std::vector<Expr> xs;
    for (int i = 0; i < 5; ++i) xs.push_back(symbol(fmt::format("s{}", i)));
    symdyn::testing::RandomExpr gen(seed, xs);
    const std::vector<Expr> coefficients{Expr(1), Expr(-1), Expr(3), rational(-1, 2)};
    auto operand = [&]() -> Expr {
      const Expr a = xs[gen.pick(xs.size())];
      const Expr b = xs[gen.pick(xs.size())];
      switch (gen.pick(4)) {
        case 0:
          return a * b;
        case 1:
          return a / (b * b + 1);
        case 2:
          return a - b;
        default:
          return coefficients[gen.pick(coefficients.size())] * a;
      }
    };
    std::vector<Expr> outputs;
    for (int k = 0; k < 8; ++k) {
      Expr sum = operand() + operand();
      if (gen.pick(2) == 0) sum = sum * operand() + operand();
      switch (gen.pick(4)) {
        case 0:
          outputs.push_back(-xs[gen.pick(xs.size())]);
          break;
        case 1:
          outputs.push_back(sin(-sum));
          break;
        case 2:
          outputs.push_back(sum);
          break;
        default:
          outputs.push_back(-sum);
          break;
      }
    }
    const Program program = compile_program(xs, outputs);
    INFO("seed " << seed << "\n" << to_string(program));
    const std::vector<double> point = gen.point();
    check_values(program, xs, outputs, point, seed % xs.size());
    CHECK(to_string(compile_program(xs, outputs)) == to_string(program));
    std::vector<Expr> reversed(outputs.rbegin(), outputs.rend());
    CHECK(compile_program(xs, reversed).operation_count() == program.operation_count());
  }
}

TEST_CASE("a negation is absorbed down a long chain of additions, up to a bound on its length",
          "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  std::vector<Expr> xs;
  for (int i = 0; i < 400; ++i) xs.push_back(symbol(fmt::format("s{}", i)));
  std::vector<double> point;
  Bindings<double> at;
  for (int i = 0; i < 400; ++i) {
    point.push_back(0.01 * i - 1.5);
    at[xs[i]] = point.back();
  }
  // -(s0 + s1 + ... + s(n-1)) with -s0 an output: (-s0) - s1 - ... as long
  // as the chain down to s0 is followed (kMaxRewriteDepth, 256).
  for (const auto& [n, negs] : {std::pair{100, 1}, std::pair{400, 2}}) {
    const Expr sum = add(std::vector<Expr>(xs.begin(), xs.begin() + n));
    const Program p = compile_program(xs, std::vector{-sum, -xs[0]});
    CHECK(p.operation_count() == ops(n - 1, 0, 0, negs));
    const auto out = run(p, point);
    CHECK(close(out[0], evaluate(-sum, at), 1e-13));
    CHECK(out[1] == -point[0]);
  }
}

TEST_CASE("powers lower to multiplications, sqrt and pow", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  const std::vector<Expr> in{x, y};
  auto with_sqrt = [](OperationCount c, int sqrt, int pow = 0) {
    c.sqrt = sqrt;
    c.pow = pow;
    return c;
  };
  CHECK(count_of(in, {pow(x, 2)}) == ops(0, 1, 0, 0));
  CHECK(count_of(in, {pow(x, 3)}) == ops(0, 2, 0, 0));
  CHECK(count_of(in, {pow(x, 8)}) == ops(0, 3, 0, 0));
  CHECK(count_of(in, {pow(x, 2), pow(x, 3), pow(x, 4)}) == ops(0, 3, 0, 0));  // x², x²·x, x²·x²
  CHECK(count_of(in, {pow(x, -1)}) == ops(0, 0, 1, 0));
  CHECK(count_of(in, {pow(x, -2)}) == ops(0, 1, 1, 0));
  CHECK(count_of(in, {y * pow(x, -2)}) == ops(0, 1, 1, 0));  // y/(x·x)
  CHECK(count_of(in, {pow(-x, 3)}) == ops(0, 2, 0, 1));
  CHECK(count_of(in, {sqrt(x)}) == with_sqrt(ops(0, 0, 0, 0), 1));
  CHECK(count_of(in, {pow(x, rational(-1, 2))}) == with_sqrt(ops(0, 0, 1, 0), 1));
  CHECK(count_of(in, {pow(x, rational(3, 2))}) == with_sqrt(ops(0, 1, 0, 0), 1));
  CHECK(count_of(in, {pow(x, rational(1, 3))}) == with_sqrt(ops(0, 0, 0, 0), 0, 1));
  CHECK(count_of(in, {pow(x, 40)}) == with_sqrt(ops(0, 0, 0, 0), 0, 1));
  const std::vector<Expr> outputs{pow(x, 7),
                                  pow(x, -3),
                                  pow(x, rational(5, 2)),
                                  pow(x, rational(-3, 2)),
                                  pow(x, rational(1, 3)),
                                  pow(x, 40),
                                  pow(x - y, 2)};
  const auto out = run(compile_program(in, outputs), {1.3, 0.4});
  const std::vector<double> want{
      std::pow(1.3, 7), std::pow(1.3, -3), std::pow(1.3, 2.5), std::pow(1.3, -1.5),
      std::cbrt(1.3),   std::pow(1.3, 40), 0.9 * 0.9};
  for (std::size_t i = 0; i < want.size(); ++i) CHECK(out[i] == Approx(want[i]).epsilon(1e-14));
}

TEST_CASE("every function kind runs in the interpreter", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  const std::vector<Expr> outputs{tan(x),      asin(x), acos(x), atan(x),
                                  atan2(y, x), exp(x),  log(y),  abs(x - y)};
  const Program p = compile_program(std::vector{x, y}, outputs);
  const double a = 0.3, b = 1.7;
  const std::vector<double> want{std::tan(a),      std::asin(a), std::acos(a), std::atan(a),
                                 std::atan2(b, a), std::exp(a),  std::log(b),  1.4};
  const auto out = run(p, {a, b});
  for (std::size_t i = 0; i < want.size(); ++i) CHECK(out[i] == Approx(want[i]).epsilon(1e-15));
  const OperationCount c = p.operation_count();
  for (Kind k : {Kind::Tan, Kind::Asin, Kind::Acos, Kind::Atan, Kind::Atan2, Kind::Exp, Kind::Log,
                 Kind::Abs}) {
    CHECK(c.call(k) == 1);
  }
  CHECK(c.total() == 9);  // eight calls and x - y
  CHECK(c.weighted() == 12 + 12 + 12 + 12 + 14 + 10 + 10 + 1 + 1);
}

TEST_CASE("emit_cpp prints one statement per instruction", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q0 = symbol("q0"), q1 = symbol("q1"), l = symbol("l");
  const std::vector<Expr> outputs{l * sin(q0) - 2 * q1, -l * cos(q0) + rational(1, 10), Expr(-3),
                                  q1, pow(q1, 2) / l};
  const Program p = compile_program(std::vector{q0, q1, l}, outputs);
  CppNaming naming;
  naming.inputs = {"q[0]", "q[1]", "p[0]"};
  naming.outputs = {"x[0]", "x[1]", "x[2]", "x[3]", "x[4]"};
  const std::string want =
      "  const double t0 = std::sin(q[0]);\n"
      "  const double t1 = std::cos(q[0]);\n"
      "  const double t2 = p[0]*t0;\n"
      "  const double t3 = 2.0*q[1];\n"
      "  const double t4 = t2 - t3;\n"
      "  const double t5 = p[0]*t1;\n"
      "  const double t6 = 0.1 - t5;\n"
      "  const double t7 = q[1]*q[1];\n"
      "  const double t8 = t7/p[0];\n"
      "  x[0] = t4;\n"
      "  x[1] = t6;\n"
      "  x[2] = -3.0;\n"
      "  x[3] = q[1];\n"
      "  x[4] = t8;\n";
  CHECK(emit_cpp(p, naming) == want);
  // Move-assigned: g++ 12 -O3 warns falsely (-Wrestrict) on assigning a short literal.
  naming.temporary_prefix = std::string(1, 'w');
  naming.scalar_type = std::string("long double");
  naming.indent.clear();
  CHECK(emit_cpp(p, naming).substr(0, 38) == "const long double w0 = std::sin(q[0]);");
  // Signs fold into a subtraction and a negation; a negative constant that
  // stays an operand is parenthesized.
  const Program n = compile_program(std::vector{q0},
                                    std::vector{-sin(q0 + rational(-5, 2)), atan2(q0, Expr(-1))});
  CppNaming one;
  one.inputs = {"q"};
  one.outputs = {"y", "z"};
  CHECK(emit_cpp(n, one) ==
        "  const double t0 = q - 2.5;\n"
        "  const double t1 = std::sin(t0);\n"
        "  const double t2 = -t1;\n"
        "  const double t3 = std::atan2(q, (-1.0));\n"
        "  y = t2;\n"
        "  z = t3;\n");
}

TEST_CASE("bad uses of compile_program, run and emit_cpp name the culprit", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");
  CHECK_THROWS_WITH(
      compile_program(std::vector{x, y}, std::vector{x * y, z + x}),
      "compile_program: output 1 uses symbol 'z', which is neither an input nor defined");
  CHECK_THROWS_WITH(compile_program(std::vector{x, y, x}, std::vector{x * y}),
                    "compile_program: symbol 'x' is given twice as an input (positions 0 and 2)");
  CHECK_THROWS_WITH(compile_program(std::vector{x, x + y}, std::vector{x}),
                    "compile_program: input 1 (x + y) is not a symbol");
  const Program p = compile_program(std::vector{x, y}, std::vector{x * y});
  std::vector<double> in{1.0};
  std::vector<double> out(1);
  std::vector<double> work(p.workspace_size());
  CHECK_THROWS_AS(p.run<double>(in, out, work), UsageError);
  CppNaming naming;
  naming.inputs = {"a"};
  naming.outputs = {"b"};
  CHECK_THROWS_WITH(emit_cpp(p, naming),
                    "emit_cpp: naming has 1 inputs and 1 outputs; the program has 2 and 1");
}

TEST_CASE("the workspace is smaller than the slot count when slots are reused", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x");
  Expr e = x;
  for (int i = 0; i < 50; ++i) e = sin(e) + x;  // a long chain: few values live at once
  const Program p = compile_program(std::vector{x}, std::vector{e});
  CHECK(p.slot_count() > 100);
  CHECK(p.workspace_size() <= 4);
  Bindings<double> at{{x, 0.7}};
  CHECK(run(p, {0.7})[0] == evaluate(e, at));
}

TEST_CASE("a definition is computed once, as its value, wherever outputs use it", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  const Expr d = symbol("d", SymbolKind::Intermediate), e = symbol("e", SymbolKind::Intermediate);
  const Expr d_value = x * y + sin(x);
  const std::vector<Definition> definitions{{e, d * d + y}, {d, d_value}};  // any order
  const std::vector<Expr> outputs{e + Expr(1), d * x, e};
  const Program p = compile_program(std::vector{x, y}, outputs, definitions);
  const Bindings<double> at{{x, 0.3}, {y, -1.7}};
  const double dv = evaluate(d_value, at);
  const std::vector<double> expected{dv * dv - 1.7 + 1, dv * 0.3, dv * dv - 1.7};
  const std::vector<double> got = run(p, {0.3, -1.7});
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(close(got[i], expected[i], 1e-15));
  CHECK(count_opcode(p, Opcode::SinCos) + count_opcode(p, Opcode::Sin) == 1);
  // Only what the outputs need: d alone needs neither e nor d·d.
  CHECK(compile_program(std::vector{x, y}, std::vector{d}, definitions).operation_count() == [] {
    OperationCount c = ops(1, 1, 0, 0);
    c.call(Kind::Sin) = 1;
    return c;
  }());
  // The schedule does not depend on the order of the definitions.
  const std::vector<Definition> reversed(definitions.rbegin(), definitions.rend());
  CHECK(to_string(compile_program(std::vector{x, y}, outputs, reversed)) == to_string(p));
}

TEST_CASE("chained definitions stay linear where substitution would flatten their sums",
          "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  // s_k = s_(k-1) + x_k·x_(k+1): substituted, s_k is a sum of k products and
  // the outputs s_1..s_n share no sum; defined, each is one more addition.
  constexpr int n = 40;
  std::vector<Expr> xs;
  for (int i = 0; i <= n; ++i) xs.push_back(symbol(fmt::format("x{}", i)));
  std::vector<Definition> definitions;
  std::vector<Expr> named, substituted;
  Expr previous_named = xs[0], previous_value = xs[0];
  for (int k = 1; k < n; ++k) {
    const Expr s = symbol(fmt::format("s{}", k), SymbolKind::Intermediate);
    definitions.push_back({s, previous_named + xs[k] * xs[k + 1]});
    previous_value = previous_value + xs[k] * xs[k + 1];
    named.push_back(s);
    substituted.push_back(previous_value);
    previous_named = s;
  }
  const Program p = compile_program(xs, named, definitions);
  CHECK(p.operation_count() == ops(n - 1, n - 1, 0, 0));
  const Program q = compile_program(xs, substituted);
  std::vector<double> point;
  for (int i = 0; i <= n; ++i) point.push_back(std::sin(i + 0.5));
  const auto a = run(p, point), b = run(q, point);
  for (std::size_t i = 0; i < a.size(); ++i) CHECK(close(a[i], b[i], 1e-14));
}

TEST_CASE("bad definitions name the culprit", "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), d = symbol("d"), e = symbol("e");
  const std::vector<Expr> in{x};
  CHECK_THROWS_WITH(
      compile_program(in, std::vector{d}, std::vector<Definition>{{d, e + x}, {e, sin(d)}}),
      Catch::Matches("compile_program: the definition of '[de]' depends on itself"));
  CHECK_THROWS_WITH(
      compile_program(in, std::vector{d}, std::vector<Definition>{{d, x}, {d, x * x}}),
      "compile_program: symbol 'd' is defined twice");
  CHECK_THROWS_WITH(compile_program(in, std::vector{x}, std::vector<Definition>{{x, Expr(2)}}),
                    "compile_program: symbol 'x' is both an input and defined");
  CHECK_THROWS_WITH(
      compile_program(in, std::vector{x}, std::vector<Definition>{{Expr(3), Expr(2)}}),
      "compile_program: a definition names '3', which is not a symbol");
  // A cycle nobody needs is never visited: only what the outputs need is compiled.
  CHECK_NOTHROW(compile_program(in, std::vector{x}, std::vector<Definition>{{d, e}, {e, d}}));
}

namespace {

// One function of every output, in parts of at most `max` statements.
struct CppParts {
  std::vector<std::string> bodies;
  std::size_t scratch_size = 0;
};
CppParts emit_cpp_parts(const Program& p, const CppNaming& naming, std::size_t max) {
  std::vector<std::size_t> all(p.output_count());
  for (std::size_t o = 0; o < all.size(); ++o) all[o] = o;
  const CppShared shared =
      emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>{all}, max);
  CppParts parts;
  for (const CppPart& part : shared.parts) parts.bodies.push_back(part.body);
  parts.scratch_size = shared.functions.front().scratch_size;
  return parts;
}

// The parts put back together: each scratch read replaced by
// the temporary last stored there, which must have been stored by an earlier
// part (a part never reads what it overwrote); scratch stores dropped. Gives
// the statements (outputs apart) and each output's right side.
struct Joined {
  std::string statements;
  std::map<std::string, std::string> outputs;  // lvalue -> value
};

Joined join_parts(const CppParts& parts) {
  Joined j;
  std::map<std::string, std::pair<std::string, std::size_t>> stored;  // s[k] -> temporary, part
  const std::regex store(R"(^  (s\[\d+\]) = (t\d+);$)"), read(R"(s\[\d+\])"),
      define(R"(^  const double )"), output(R"(^  (\w+\[\d+\]|\w+) = (.*);$)");
  for (std::size_t p = 0; p < parts.bodies.size(); ++p) {
    std::istringstream lines(parts.bodies[p]);
    for (std::string line; std::getline(lines, line);) {
      std::smatch m;
      if (std::regex_match(line, m, store)) {
        stored[m[1]] = {m[2], p};
        continue;
      }
      std::string resolved;
      auto last = line.cbegin();
      for (std::sregex_iterator it(line.begin(), line.end(), read), end; it != end; ++it) {
        const auto& [name, part] = stored.at(it->str());
        CHECK(part < p);
        resolved.append(last, (*it)[0].first).append(name);
        last = (*it)[0].second;
      }
      resolved.append(last, line.cend());
      if (std::regex_search(resolved, define)) {
        j.statements += resolved + "\n";
      } else if (std::regex_match(resolved, m, output)) {
        CHECK(j.outputs.emplace(m[1], m[2]).second);
      }
    }
  }
  return j;
}

Joined join_whole(const std::string& body) {
  CppParts one;
  one.bodies = {body};
  return join_parts(one);
}

}  // namespace

TEST_CASE(
    "emit_cpp_shared, one function: the parts are the whole program, values crossing parts through "
    "the scratch array",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> xs{symbol("x0"), symbol("x1"), symbol("x2")};
  for (unsigned seed = 0; seed < 300; ++seed) {
    symdyn::testing::RandomExpr gen(seed, xs);
    std::vector<Expr> outputs;
    for (int i = 0; i < 6; ++i) outputs.push_back(gen(5));
    outputs.push_back(Expr(2));  // a constant output: assigned by some part
    outputs.push_back(xs[1]);    // an input output
    const Program p = compile_program(xs, outputs);
    CppNaming naming;
    naming.inputs = {"x[0]", "x[1]", "x[2]"};
    for (std::size_t i = 0; i < outputs.size(); ++i)
      naming.outputs.push_back(fmt::format("y[{}]", i));
    const std::string whole = emit_cpp(p, naming);
    const Joined expected = join_whole(whole);
    for (std::size_t max : {1, 2, 3, 7, 40}) {
      INFO("seed " << seed << ", parts of " << max << "\n" << whole);
      const CppParts parts = emit_cpp_parts(p, naming, max);
      std::size_t computing = 0;
      for (const Instruction& i : p.instructions())
        computing += i.op != Opcode::Const && i.op != Opcode::Input;
      // Fewest parts of at most max statements (instructions and outputs).
      CHECK(parts.bodies.size() >= (computing + max - 1) / max);
      CHECK(parts.bodies.size() <= (computing + outputs.size() + max - 1) / max);
      const Joined joined = join_parts(parts);
      CHECK(joined.statements == expected.statements);
      CHECK(joined.outputs == expected.outputs);
      if (parts.bodies.size() == 1) CHECK(parts.scratch_size == 0);
    }
    CHECK(emit_cpp_parts(p, naming, 0).bodies == std::vector{whole});
    // A limit at least the program's statements: one part, as emit_cpp prints it.
    std::size_t statements = outputs.size();
    for (const Instruction& i : p.instructions())
      statements += i.op != Opcode::Const && i.op != Opcode::Input;
    CHECK(emit_cpp_parts(p, naming, statements).bodies == std::vector{whole});
  }
}

namespace {

std::size_t count_definitions(const std::string& statements) {
  std::size_t n = 0;
  for (std::size_t at = statements.find("const double "); at != std::string::npos;
       at = statements.find("const double ", at + 1))
    ++n;
  return n;
}

// Values computed by the program's instructions (a sincos defines two).
std::size_t computed_values(const Program& p) {
  std::size_t n = 0;
  for (const Instruction& i : p.instructions()) {
    if (i.op != Opcode::Const && i.op != Opcode::Input)
      n += static_cast<std::size_t>(info(i.op).results);
  }
  return n;
}

// Each output's value as one expression: the joined statements' temporaries
// replaced by what they are defined as, recursively (the numbering of
// temporaries apart, what the printed code computes).
std::map<std::string, std::string> expanded_outputs(const Joined& joined) {
  const std::regex define(R"(^  const double (t\d+) = (.*);$)"), temporary(R"(t\d+)");
  std::map<std::string, std::string> definitions, expanded, outputs;
  std::istringstream lines(joined.statements);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    REQUIRE(std::regex_match(line, m, define));
    definitions[m[1]] = m[2];
  }
  std::function<std::string(const std::string&)> expand = [&](const std::string& text) {
    std::string out;
    auto last = text.cbegin();
    for (std::sregex_iterator it(text.begin(), text.end(), temporary), end; it != end; ++it) {
      const std::string name = it->str();
      if (!expanded.contains(name)) {
        std::string e(1, '(');
        e += expand(definitions.at(name));
        e += ')';
        expanded[name] = std::move(e);
      }
      out.append(last, (*it)[0].first).append(expanded[name]);
      last = (*it)[0].second;
    }
    return out.append(last, text.cend());
  };
  for (const auto& [lvalue, value] : joined.outputs) outputs[lvalue] = expand(value);
  return outputs;
}

}  // namespace

TEST_CASE(
    "emit_cpp_shared: each function's parts compute its outputs, and no other, sharing statements",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> xs{symbol("x0"), symbol("x1"), symbol("x2")};
#ifdef __SANITIZE_ADDRESS__
  constexpr unsigned seeds = 40;  // the sanitizers make a seed 20 times slower
#else
  constexpr unsigned seeds = 200;
#endif
  for (unsigned seed = 0; seed < seeds; ++seed) {
    symdyn::testing::RandomExpr gen(seed, xs);
    // Outputs built on each other (the functions share work), a constant and an input.
    std::vector<Expr> outputs;
    for (int i = 0; i < 8; ++i)
      outputs.push_back(i < 2 ? gen(4)
                              : gen(3) * outputs[static_cast<std::size_t>(i) / 2] + gen(2));
    outputs.push_back(Expr(2));
    outputs.push_back(xs[1]);
    const Program p = compile_program(xs, outputs);
    CppNaming naming;
    naming.inputs = {"x[0]", "x[1]", "x[2]"};
    naming.input_arrays = {{"x", 3}};
    for (std::size_t i = 0; i < outputs.size(); ++i)
      naming.outputs.push_back(fmt::format("y[{}]", i));
    naming.output_arrays = {{"y", outputs.size()}};
    // Functions of overlapping outputs; together they want every output.
    std::vector<std::vector<std::size_t>> functions{
        {0, 1}, {0, 1, 2, 3}, {4, 6, 8}, {5, 7, 9}, {3, 8}};
    for (std::size_t max : {2, 5, 11, 0}) {
      INFO("seed " << seed << ", parts of " << max);
      const CppShared shared = emit_cpp_shared(p, naming, functions, max);
      REQUIRE(shared.functions.size() == functions.size());
      std::size_t definitions =
          0;  // in all parts: each computed value is defined once, in one part
      for (const CppPart& part : shared.parts) {
        definitions += count_definitions(part.body);
        const bool reads_x = part.body.find("x[") != std::string::npos;
        CHECK(part.input_arrays ==
              (reads_x ? std::vector<std::size_t>{0} : std::vector<std::size_t>{}));
        const bool writes_y = part.body.find("y[") != std::string::npos;
        CHECK(part.output_arrays ==
              (writes_y ? std::vector<std::size_t>{0} : std::vector<std::size_t>{}));
        CHECK(part.scratch == (part.body.find("s[") != std::string::npos));
      }
      CHECK(definitions == computed_values(p));
      for (std::size_t f = 0; f < functions.size(); ++f) {
        INFO("function " << f);
        CppParts mine;
        for (std::size_t part : shared.functions[f].parts) {
          CHECK(std::find(shared.parts[part].functions.begin(), shared.parts[part].functions.end(),
                          f) != shared.parts[part].functions.end());
          mine.bodies.push_back(shared.parts[part].body);
        }
        CHECK(std::is_sorted(shared.functions[f].parts.begin(), shared.functions[f].parts.end()));
        const Joined joined = join_parts(mine);
        // Exactly the instructions its outputs need...
        const Program alone = p.subprogram(functions[f], std::vector<std::size_t>{0, 1, 2});
        CHECK(count_definitions(joined.statements) == computed_values(alone));
        // ... and its outputs, each assigned once (join_parts), to what the program computes.
        CppNaming own;
        own.inputs = naming.inputs;
        for (std::size_t o : functions[f]) own.outputs.push_back(naming.outputs[o]);
        CHECK(expanded_outputs(joined) == expanded_outputs(join_whole(emit_cpp(alone, own))));
      }
    }
  }
  const Program p = compile_program(xs, std::vector{xs[0] * xs[1], Expr(1)});
  CppNaming naming;
  naming.inputs = {"x[0]", "x[1]", "x[2]"};
  naming.outputs = {"y[0]", "y[1]"};
  CHECK_THROWS_WITH(emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>{{0}}, 4),
                    "emit_cpp_shared: no function wants output 1");
  CHECK_THROWS_WITH(emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>{{0, 1, 2}}, 4),
                    "emit_cpp_shared: function 0 lists output 2; the program has 2");
  CHECK_THROWS_WITH(
      emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>(65, {0, 1}), 4),
      "emit_cpp_shared: 65 functions, at most 64");
}

TEST_CASE("Program::subprogram: some outputs over some inputs, the instructions they need",
          "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");
  const Program p =
      compile_program(std::vector{x, y, z}, std::vector{sin(x) * y, cos(x) + z, y * z});
  const Program sub =
      p.subprogram(std::vector<std::size_t>{1}, std::vector<std::size_t>{2, 0});  // over (z, x)
  CHECK(sub.input_count() == 2);
  CHECK(sub.output_count() == 1);
  CHECK(sub.operation_count().total() == 2);  // sincos (kept whole) and one add
  const std::vector<double> out = sub.evaluate<double>(std::vector{0.5, 0.3});
  CHECK(out[0] == Approx(std::cos(0.3) + 0.5));
  CHECK_THROWS_WITH(p.subprogram(std::vector<std::size_t>{2}, std::vector<std::size_t>{1}),
                    "subprogram: the outputs need input 2, which is not given");
  CHECK_THROWS_WITH(p.subprogram(std::vector<std::size_t>{3}, std::vector<std::size_t>{}),
                    "subprogram: no output 3");
}

TEST_CASE(
    "emit_cpp_shared, one function: in several parts, a computed output is assigned right after "
    "its definition",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> xs{symbol("x0"), symbol("x1"), symbol("x2")};
  const std::regex define(R"(^  const double (t\d+) = .*;$)"), store(R"(^  s\[\d+\] = (t\d+);$)"),
      output(R"(^  y\[\d+\] = (.*);$)"), temporary(R"(t\d+)");
  for (unsigned seed = 0; seed < 200; ++seed) {
    symdyn::testing::RandomExpr gen(seed, xs);
    std::vector<Expr> outputs;
    for (int i = 0; i < 6; ++i) outputs.push_back(gen(5));
    outputs.push_back(outputs[seed % 6]);  // a value assigned twice
    outputs.push_back(Expr(2));
    outputs.push_back(xs[1]);
    const Program p = compile_program(xs, outputs);
    CppNaming naming;
    naming.inputs = {"x[0]", "x[1]", "x[2]"};
    for (std::size_t i = 0; i < outputs.size(); ++i)
      naming.outputs.push_back(fmt::format("y[{}]", i));
    for (std::size_t max : {2, 5, 11}) {
      const CppParts parts = emit_cpp_parts(p, naming, max);
      if (parts.bodies.size() < 2) continue;
      INFO("seed " << seed << ", parts of " << max);
      std::size_t assigned = 0;
      for (const std::string& body : parts.bodies) {
        INFO(body);
        std::istringstream lines(body);
        std::string last;    // the temporary defined by the last definition line, if no other
                             // statement followed
        bool loads = false;  // the part's outputs that are loads, at its end
        for (std::string line; std::getline(lines, line);) {
          std::smatch m;
          if (std::regex_match(line, m, define)) {
            CHECK_FALSE(loads);
            last = m[1];
          } else if (std::regex_match(line, m, store)) {
            CHECK(m[1] == last);  // a scratch store follows its definition too
          } else if (std::regex_match(line, m, output)) {
            ++assigned;
            if (std::regex_match(m[1].str(), temporary)) {
              CHECK(m[1] == last);
            } else {
              loads = true;  // a constant or an input (or a scratch entry: never, values are
                             // assigned in their part)
              CHECK_FALSE(std::regex_search(m[1].str(), std::regex(R"(s\[)")));
            }
          } else {
            FAIL("unexpected line: " << line);
          }
        }
      }
      CHECK(assigned == outputs.size());
    }
  }
}

TEST_CASE(
    "emit_cpp zeroes a long output array of many zeros by one loop, then assigns its other "
    "elements",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x");
  static_assert(kZeroedArrayShare == 2);
  const std::size_t n = kMinZeroedArray;
  // a: half zeros (zeroed); b: zeros, but short (each assigned); c: fewer than half zeros (each
  // assigned).
  std::vector<Expr> outputs;
  for (std::size_t i = 0; i < n; ++i)
    outputs.push_back(i % 2 == 0 ? Expr(0) : sin(x) * Expr(static_cast<int>(i)));
  for (std::size_t i = 0; i + 1 < n; ++i) outputs.push_back(Expr(0));
  for (std::size_t i = 0; i < n; ++i) outputs.push_back(i < n / 2 - 1 ? Expr(0) : x);
  const Program p = compile_program(std::vector{x}, outputs);
  CppNaming naming;
  naming.inputs = {"x"};
  naming.output_arrays = {{"a", n}, {"b", n - 1}, {"c", n}};
  for (const auto& [name, size] : naming.output_arrays) {
    for (std::size_t i = 0; i < size; ++i) naming.outputs.push_back(fmt::format("{}[{}]", name, i));
  }
  const std::string code = emit_cpp(p, naming);
  // a zeroed first, once; its odd elements assigned after, its zeros never.
  CHECK(code.rfind(fmt::format("  for (int i = 0; i < {}; ++i) a[i] = 0.0;\n", n), 0) == 0);
  CHECK(code.find("for (", 3) == std::string::npos);  // one loop only
  CHECK_THAT(code, Catch::Contains("  a[1] = ") && !Catch::Contains("  a[0] = ") &&
                       !Catch::Contains("  a[2] = "));
  CHECK_THAT(code, Catch::Contains("  b[0] = 0.0;\n") &&
                       Catch::Contains(fmt::format("  b[{}] = 0.0;\n", n - 2)));
  CHECK_THAT(code, Catch::Contains("  c[0] = 0.0;\n") &&
                       Catch::Contains(fmt::format("  c[{}] = x;\n", n - 1)));
  naming.output_arrays.pop_back();
  CHECK_THROWS_WITH(emit_cpp(p, naming),
                    fmt::format("emit_cpp: naming's output arrays have {} elements; the "
                                "program has {} outputs",
                                2 * n - 1, outputs.size()));
}

TEST_CASE(
    "emit_cpp: an array written sparsely has its zeros never written, by a loop or one by one",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x");
  const std::size_t n = kMinZeroedArray;
  // a: half zeros, long; b: zeros, short; both sparse. c: half zeros, long, written whole.
  std::vector<Expr> outputs;
  for (std::size_t i = 0; i < n; ++i)
    outputs.push_back(i % 2 == 0 ? Expr(0) : sin(x) * Expr(static_cast<int>(i)));
  for (std::size_t i = 0; i < 3; ++i) outputs.push_back(i == 1 ? x : Expr(0));
  for (std::size_t i = 0; i < n; ++i) outputs.push_back(i % 2 == 0 ? Expr(0) : x);
  const Program p = compile_program(std::vector{x}, outputs);
  CppNaming naming;
  naming.inputs = {"x"};
  naming.output_arrays = {{"a", n}, {"b", 3}, {"c", n}};
  naming.sparse_arrays = {true, true, false};
  for (const auto& [name, size] : naming.output_arrays) {
    for (std::size_t i = 0; i < size; ++i) naming.outputs.push_back(fmt::format("{}[{}]", name, i));
  }
  for (std::size_t max : {0, 5}) {
    INFO("parts of " << max);
    std::vector<std::size_t> all(outputs.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    std::string code;
    for (const CppPart& part :
         emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>{all}, max).parts)
      code += part.body;
    // Only c is zeroed by a loop; a's and b's nonzeros are written, their zeros never.
    CHECK_THAT(code, Catch::Contains(fmt::format("for (int i = 0; i < {}; ++i) c[i] = 0.0;", n)));
    CHECK(code.find("for (") == code.rfind("for ("));
    for (std::size_t i = 0; i < n; ++i) {
      INFO("a[" << i << "]");
      CHECK((code.find(fmt::format("  a[{}] = ", i)) != std::string::npos) == (i % 2 == 1));
    }
    CHECK_THAT(code, Catch::Contains("  b[1] = x;\n") && !Catch::Contains("  b[0] = ") &&
                         !Catch::Contains("  b[2] = "));
  }
  naming.sparse_arrays.pop_back();
  CHECK_THROWS_WITH(emit_cpp(p, naming),
                    "emit_cpp: naming says of 2 arrays whether they are "
                    "sparse; it has 3 output arrays");
}

TEST_CASE(
    "emit_cpp_shared: an array of many zeros is zeroed before any of its elements is assigned",
    "[program]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> xs{symbol("x0"), symbol("x1"), symbol("x2")};
  const std::regex zero_loop(R"(^  for \(int i = 0; i < (\d+); \+\+i\) y\[i\] = 0\.0;$)"),
      output(R"(^  y\[(\d+)\] = (.*);$)");
  for (unsigned seed = 0; seed < 100; ++seed) {
    symdyn::testing::RandomExpr gen(seed, xs);
    // y: a few values among zeros (most of it), z: values only.
    std::vector<Expr> outputs;
    for (unsigned k = 0; k < 5; ++k) {
      outputs.push_back(gen(4));
      outputs.insert(outputs.end(), (seed * 7 + k * 11) % 20 + kMinZeroedArray / 4, Expr(0));
    }
    const std::size_t ny = outputs.size();
    for (unsigned k = 0; k < 5; ++k) outputs.push_back(gen(4) * outputs[k]);
    const Program p = compile_program(xs, outputs);
    CppNaming naming;
    naming.inputs = {"x[0]", "x[1]", "x[2]"};
    for (std::size_t i = 0; i < ny; ++i) naming.outputs.push_back(fmt::format("y[{}]", i));
    for (std::size_t i = ny; i < outputs.size(); ++i)
      naming.outputs.push_back(fmt::format("z[{}]", i - ny));
    naming.output_arrays = {{"y", ny}, {"z", outputs.size() - ny}};
    std::vector<std::size_t> all(outputs.size());
    for (std::size_t o = 0; o < all.size(); ++o) all[o] = o;
    for (std::size_t max : {3, 10, 40}) {
      INFO("seed " << seed << ", parts of " << max);
      const CppShared shared =
          emit_cpp_shared(p, naming, std::vector<std::vector<std::size_t>>{all}, max);
      // Played in order: y zeroed once, first; then each nonzero element assigned once, the zeros
      // never.
      bool zeroed = false;
      std::set<std::size_t> assigned;
      for (const CppPart& part : shared.parts) {
        std::istringstream lines(part.body);
        for (std::string line; std::getline(lines, line);) {
          std::smatch m;
          if (std::regex_match(line, m, zero_loop)) {
            CHECK_FALSE(zeroed);
            CHECK(assigned.empty());
            CHECK(std::stoul(m[1]) == ny);
            zeroed = true;
          } else if (std::regex_match(line, m, output)) {
            CHECK(zeroed);
            CHECK(assigned.insert(std::stoul(m[1])).second);
            CHECK(m[2] != "0.0");
          }
        }
      }
      CHECK(zeroed);
      std::set<std::size_t> nonzero;
      for (std::size_t o = 0; o < ny; ++o) {
        if (!(outputs[o] == Expr(0))) nonzero.insert(o);
      }
      CHECK(assigned == nonzero);
    }
  }
}
