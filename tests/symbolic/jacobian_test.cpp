// Jacobians through chains of definitions (chain_jacobian) and the directional
// derivative, checked against the complex step on the program of the
// definitions: independent of the engine's calculus, which only evaluates.
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>

#include "support/random_expr.hpp"
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/jacobian.hpp>
#include <symdyn/symbolic/program.hpp>

using namespace symdyn::symbolic;
using symdyn::testing::RandomExpr;
using Complex = std::complex<double>;

namespace {

constexpr int kCases = 400;

bool close(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max({1.0, std::abs(a), std::abs(b)});
}

// A random chain s_k = e_k(x, s_0 .. s_{k-1}), none a constant, and outputs over all of them.
struct RandomChain {
  std::vector<Expr> variables;
  std::vector<Definition> definitions;
  std::vector<Expr> outputs;
};

RandomChain random_chain(unsigned seed) {
  RandomChain c;
  c.variables = {symbol("x", SymbolKind::Variable), symbol("y", SymbolKind::Variable),
                 symbol("z", SymbolKind::Rate)};
  std::vector<Expr> reachable = c.variables;
  RandomExpr first(seed, reachable);
  const std::size_t n = 1 + first.pick(6);
  for (std::size_t k = 0; k < n; ++k) {
    RandomExpr gen(seed * 31 + static_cast<unsigned>(k), reachable);
    const Expr s = symbol(fmt::format("s{}", k), SymbolKind::Intermediate);
    // Not a constant: abs(y·sin(s)) with s = 0 would be differentiated at abs's kink.
    Expr value = gen(3);
    while (value.is_number()) value = gen(3);
    c.definitions.push_back({s, value});
    reachable.push_back(s);
  }
  RandomExpr gen(seed * 7 + 3, reachable);
  for (int i = 0; i < 3; ++i) c.outputs.push_back(gen(3));
  return c;
}

// The outputs at `point` (complex), through the definitions.
std::vector<Complex> outputs_at(const RandomChain& c, const std::vector<Complex>& point) {
  const Program p = compile_program(c.variables, c.outputs, c.definitions);
  return p.evaluate<Complex>(point);
}

}  // namespace

TEST_CASE("chain_jacobian matches the complex step through random chains of definitions",
          "[jacobian][property]") {
  int compared = 0;
  for (unsigned seed = 0; seed < kCases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const RandomChain c = random_chain(seed);
    const ChainJacobian J = chain_jacobian(c.outputs, c.variables, c.definitions);
    REQUIRE(J.entries.size() == c.outputs.size() * c.variables.size());
    std::vector<Definition> all = c.definitions;
    all.insert(all.end(), J.definitions.begin(), J.definitions.end());
    const Program jacobian = compile_program(c.variables, J.entries, all);
    RandomExpr points(seed + 1000, c.variables);
    const std::vector<double> p = points.point();
    // A definition exactly 0 there (atan2(0, u) is not folded) may put abs at its kink.
    std::vector<Expr> defined;
    for (const Definition& d : c.definitions) defined.push_back(d.symbol);
    const std::vector<double> at_p =
        compile_program(c.variables, defined, c.definitions).evaluate<double>(p);
    if (std::find(at_p.begin(), at_p.end(), 0.0) != at_p.end()) continue;
    const std::vector<double> values = jacobian.evaluate<double>(p);
    for (std::size_t j = 0; j < c.variables.size(); ++j) {
      constexpr double h = 1e-30;
      std::vector<Complex> z(p.begin(), p.end());
      z[j] += Complex(0.0, h);
      const std::vector<Complex> f = outputs_at(c, z);
      for (std::size_t i = 0; i < c.outputs.size(); ++i) {
        const double expected = f[i].imag() / h;
        const double got = values[i * c.variables.size() + j];
        if (!std::isfinite(expected) || std::abs(expected) > 1e8)
          continue;  // a steep point: no comparison
        INFO("seed " << seed << ", output " << i << " = " << c.outputs[i] << ", variable "
                     << c.variables[j] << ": " << got << " against " << expected);
        CHECK(close(got, expected, 1e-9));
        ++compared;
      }
    }
  }
  CHECK(compared > kCases * 6);
}

TEST_CASE("chain_jacobian names each reached derivative once and skips the rest", "[jacobian]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x", SymbolKind::Variable), y = symbol("y", SymbolKind::Variable);
  const Expr a = symbol("a", SymbolKind::Intermediate), b = symbol("b", SymbolKind::Intermediate);
  const Expr unused = symbol("unused", SymbolKind::Intermediate);
  // a = sin(x)·y, unused = exp(x), b = a² + x; out = b·cos(a) + y
  const std::vector<Definition> defs{{a, sin(x) * y}, {unused, exp(x)}, {b, pow(a, 2) + x}};
  const std::vector<Expr> out{b * cos(a) + y};
  const std::vector<Expr> vars{x, y};
  const ChainJacobian J = chain_jacobian(out, vars, defs);
  // d(a)/d(x), d(b)/d(x), d(a)/d(y), d(b)/d(y): unused is not reached.
  REQUIRE(J.definitions.size() == 4);
  for (const Definition& d : J.definitions)
    CHECK(d.symbol.name().find("unused") == std::string::npos);
  CHECK(J.definitions[0].symbol.name() == "d(a)/d(x)");
  // Closed form at (x, y) = (0.3, -1.2).
  const double xv = 0.3, yv = -1.2;
  const double av = std::sin(xv) * yv, bv = av * av + xv;
  const double da_dx = std::cos(xv) * yv, da_dy = std::sin(xv);
  const double db_dx = 2 * av * da_dx + 1, db_dy = 2 * av * da_dy;
  const auto d_out = [&](double da, double db, double dy) {
    return db * std::cos(av) - bv * std::sin(av) * da + dy;
  };
  std::vector<Definition> all = defs;
  all.insert(all.end(), J.definitions.begin(), J.definitions.end());
  const std::vector<double> values =
      compile_program(vars, J.entries, all).evaluate<double>(std::vector<double>{xv, yv});
  CHECK(values[0] == Approx(d_out(da_dx, db_dx, 0.0)).epsilon(1e-14));
  CHECK(values[1] == Approx(d_out(da_dy, db_dy, 1.0)).epsilon(1e-14));
}

TEST_CASE("chain_jacobian: a derivative that is a number or a symbol is not named", "[jacobian]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x", SymbolKind::Variable), c = symbol("c", SymbolKind::Parameter);
  const Expr a = symbol("a", SymbolKind::Intermediate), b = symbol("b", SymbolKind::Intermediate);
  // da/dx = c, a symbol, and so db/dx: neither is a definition.
  const std::vector<Definition> defs{{a, c * x}, {b, a + 1}};
  const std::vector<Expr> out{2 * b};
  const std::vector<Expr> vars{x};
  const ChainJacobian J = chain_jacobian(out, vars, defs);
  CHECK(J.definitions.empty());
  CHECK(J.entries[0] == 2 * c);
}

TEST_CASE("chain_jacobian refuses a variable that is not a symbol or is defined",
          "[jacobian][error]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x", SymbolKind::Variable), a = symbol("a", SymbolKind::Intermediate);
  const std::vector<Definition> defs{{a, sin(x)}};
  const std::vector<Expr> out{a};
  const std::vector<Expr> not_symbol{x + 1}, defined{a};
  CHECK_THROWS_WITH(chain_jacobian(out, not_symbol, defs),
                    Catch::Contains("'1 + x' is not a symbol"));
  CHECK_THROWS_WITH(chain_jacobian(out, defined, defs), Catch::Contains("'a' is defined"));
}

TEST_CASE("DirectionalDerivative is the sum of partials times tangents", "[jacobian]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x", SymbolKind::Variable), y = symbol("y", SymbolKind::Rate),
             t = symbol("t", SymbolKind::Time);
  const Expr e = sin(x) * y + t;
  DirectionalDerivative d(std::unordered_map<Expr, Expr>{{x, Expr(2)}, {y, Expr(3)}});
  // 2·cos(x)·y + 3·sin(x); the time symbol, absent, is a constant here.
  CHECK(d(e) == 2 * cos(x) * y + 3 * sin(x));
  CHECK_THROWS_WITH(d.add(x, Expr(1)), Catch::Contains("'x' is already met or given"));
}
