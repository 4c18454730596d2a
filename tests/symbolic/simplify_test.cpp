#include <fmt/format.h>

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <map>
#include <unordered_set>

#include "support/random_expr.hpp"
#include "support/rotation_exprs.hpp"
#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/detail/trig_rules.hpp>
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/rewrite.hpp>
#include <symdyn/symbolic/simplify.hpp>

using namespace symdyn::symbolic;
using namespace symdyn::testing::rotation_exprs;

namespace {

void collect_symbols(Expr e, std::vector<Expr>* out, std::unordered_set<std::uint32_t>* seen) {
  if (!seen->insert(e.id()).second) return;
  if (e.is_symbol()) out->push_back(e);
  for (Expr a : e.args()) collect_symbols(a, out, seen);
}

// a and b agree at `points` random points with every symbol in [-2, 2]
// (relative tolerance with an absolute floor).
bool same_values(Expr a, Expr b, std::mt19937& rng, int points = 4) {
  std::vector<Expr> symbols;
  std::unordered_set<std::uint32_t> seen;
  collect_symbols(a, &symbols, &seen);
  collect_symbols(b, &symbols, &seen);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < points; ++k) {
    Bindings<double> at;
    for (Expr s : symbols) at[s] = u(rng);
    const double va = evaluate(a, at);
    const double vb = evaluate(b, at);
    if (!std::isfinite(va)) continue;  // outside the domain of the input
    if (std::abs(va - vb) > 1e-9 * std::max({1.0, std::abs(va), std::abs(vb)})) return false;
  }
  return true;
}

// A sum of products of sines and cosines of a few angles (and sums of them),
// with small rational coefficients and symbolic factors: the kinematics shape.
Expr random_trig(std::mt19937& rng, std::span<const Expr> angles, std::span<const Expr> factors) {
  auto pick = [&](std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  const std::size_t n_terms = 1 + pick(5);
  Expr sum = 0;
  for (std::size_t t = 0; t < n_terms; ++t) {
    Expr term =
        rational(static_cast<std::int64_t>(pick(7)) - 3, 1 + static_cast<std::int64_t>(pick(2)));
    if (term.is_zero()) term = 1;
    const std::size_t n_factors = 1 + pick(3);
    for (std::size_t f = 0; f < n_factors; ++f) {
      Expr angle = angles[pick(angles.size())];
      if (pick(4) == 0) angle = angle + angles[pick(angles.size())];
      Expr g = pick(2) == 0 ? sin(angle) : cos(angle);
      if (pick(3) == 0) g = pow(g, 2);
      term = term * g;
    }
    if (pick(2) == 0) term = term * factors[pick(factors.size())];
    sum = sum + term;
  }
  return sum;
}

}  // namespace

// ---------------------------------------------------------------- cost model

TEST_CASE("operation_cost counts each operation of the DAG once", "[simplify][cost]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");
  CHECK(operation_cost(x) == 0);
  CHECK(operation_cost(Expr(3)) == 0);
  CHECK(operation_cost(x + y) == 1);
  CHECK(operation_cost(x + y + z) == 2);
  CHECK(operation_cost(x * y * z) == 2);
  CHECK(operation_cost(3 * x) == 1);
  CHECK(operation_cost(2 * x * y) == 2);
  CHECK(operation_cost(-x) == 0);     // folds into a subtraction
  CHECK(operation_cost(x - y) == 1);  // a subtraction
  CHECK(operation_cost(x - 2 * y) == 2);
  CHECK(operation_cost(pow(x, 2)) == 1);
  CHECK(operation_cost(pow(x, 3)) == 2);
  CHECK(operation_cost(pow(x, 4)) == 2);
  CHECK(operation_cost(pow(x, 5)) == 3);
  CHECK(operation_cost(1 / x) == 1);
  CHECK(operation_cost(x / y) == 1);  // the division replaces the multiply
  CHECK(operation_cost(x / pow(y, 2)) == 2);
  CHECK(operation_cost(sqrt(x)) == info(Kind::Pow).cost);
  CHECK(operation_cost(sin(x)) == info(Kind::Sin).cost);
  CHECK(operation_cost(atan2(x, y)) == info(Kind::Atan2).cost);
  // sin(x) is shared: counted once.
  CHECK(operation_cost(sin(x) + y * sin(x)) == info(Kind::Sin).cost + 2);
  const std::vector<Expr> outputs{y * sin(x), z * sin(x)};
  CHECK(operation_cost(outputs) == info(Kind::Sin).cost + 2);
  CHECK(operation_cost(outputs) < operation_cost(outputs[0]) + operation_cost(outputs[1]));
}

// ---------------------------------------------------------------- matching

TEST_CASE("a sum pattern matches a subset of the terms, in any order", "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = wildcard("_a"), x = wildcard("_x");
  const Expr q = symbol("q"), y = symbol("y"), z = symbol("z");
  const auto ms = find_matches(a * pow(sin(x), 2) + a * pow(cos(x), 2),
                               3 * y * pow(sin(q), 2) + z + 3 * y * pow(cos(q), 2));
  REQUIRE(ms.size() == 1);
  CHECK(ms[0][a] == 3 * y);
  CHECK(ms[0][x] == q);
  REQUIRE(ms[0].remainder.size() == 1);
  CHECK(ms[0].remainder[0] == z);
  // Different cofactors: no match.
  CHECK(
      find_matches(a * pow(sin(x), 2) + a * pow(cos(x), 2), 3 * pow(sin(q), 2) + 2 * pow(cos(q), 2))
          .empty());
}

TEST_CASE("a product pattern matches a sub-multiset of the factors, the cofactor takes the rest",
          "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = wildcard("_a"), x = wildcard("_x"), y = wildcard("_y");
  const Expr q = symbol("q"), q1 = symbol("q1"), v = symbol("v");
  // A power counts as repeated factors: sin(_x) inside sin(q)^3.
  auto ms = find_matches(a * sin(x), 2 * v * pow(sin(q), 3));
  REQUIRE(ms.size() == 1);
  CHECK(ms[0][a] == 2 * v * pow(sin(q), 2));
  // The cofactor can be a bare number, and a lone factor is a product.
  ms = find_matches(a * sin(x), sin(q));
  REQUIRE(ms.size() == 1);
  CHECK(ms[0][a] == Expr(1));
  // The coefficient of the pattern divides the target's.
  ms = find_matches(-2 * a * cos(x), 3 * cos(q));
  REQUIRE(ms.size() == 1);
  CHECK(ms[0][a] == rational(-3, 2));
  // Commutativity: both assignments of x and y.
  ms = find_matches(cos(x) * cos(y), cos(q) * cos(q1));
  CHECK(ms.size() == 2);
  // Without a cofactor the leftover must be 1.
  CHECK(find_matches(cos(x) * cos(y), 2 * cos(q) * cos(q1)).empty());
  CHECK(find_matches(cos(x) * cos(y), v * cos(q) * cos(q1)).empty());
  // A repeated wildcard must bind the same expression.
  CHECK(find_matches(a * sin(x) * cos(x), sin(q) * cos(q1)).empty());
  CHECK(find_matches(a * sin(x) * cos(x), v * sin(q) * cos(q)).size() == 1);
}

TEST_CASE("a nested sum pattern needs a rest wildcard for leftover terms", "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = wildcard("_x"), y = wildcard("_y"), rest = wildcard("_R");
  const Expr p = symbol("p"), q = symbol("q"), r = symbol("r");
  CHECK(find_matches(sin(x + rest), sin(p + q + r)).size() == 3);
  CHECK(find_matches(sin(x + y), sin(p + q + r)).empty());
  CHECK(find_matches(sin(x + y), sin(p + q)).size() == 2);
  const auto ms = find_matches(sin(x + rest), sin(p + q + r));
  CHECK(instantiate(rest, ms[0]) + instantiate(x, ms[0]) == p + q + r);
}

TEST_CASE("rule rows are checked when they are made", "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = wildcard("_a"), b = wildcard("_b"), x = wildcard("_x");
  CHECK_THROWS_WITH(rule("bad", sin(x), cos(a)), Catch::Contains("'bad'") && Catch::Contains("_a"));
  CHECK_THROWS_WITH(rule("bare", x, x), Catch::Contains("'bare'"));
  CHECK_THROWS_WITH(rule("two cofactors", a * b * sin(x), a), Catch::Contains("'two cofactors'"));
  CHECK_THROWS_AS(wildcard("x"), UsageError);
}

TEST_CASE("conditions are sound: unknown means no", "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr y = symbol("y"), q = symbol("q");
  CHECK(is_nonnegative(pow(y, 2) + 1));
  CHECK(is_nonnegative(sqrt(y) * exp(q)));
  CHECK_FALSE(is_nonnegative(y));
  CHECK_FALSE(is_nonnegative(sin(q)));
  CHECK_FALSE(is_nonnegative(pow(y, 3)));
  CHECK(simplify(abs(pow(y, 2) + 1)) == pow(y, 2) + 1);
  CHECK(simplify(abs(y) + 1) == abs(y) + 1);
  CHECK(simplify(sqrt(pow(sin(q), 2))) == abs(sin(q)));
}

TEST_CASE("the Improve strategy only accepts cheaper rewrites", "[simplify][rewrite]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q"), q1 = symbol("q1");
  Rewriter contract(contracting_trig_rules(), Strategy::Improve);
  const Expr e = cos(q) * cos(q1) - sin(q) * sin(q1);
  CHECK(contract(e) == cos(q + q1));
  // sin q cos q alone is contracted (one call instead of two) ...
  CHECK(contract(sin(q) * cos(q)) == sin(2 * q) / 2);
  // ... but an expanding table under Improve never fires (it only adds calls).
  Rewriter expand_trig(expanding_trig_rules(), Strategy::Improve);
  CHECK(expand_trig(sin(q + q1)) == sin(q + q1));
  Rewriter normalize(expanding_trig_rules(), Strategy::Normalize);
  CHECK(normalize(sin(q + q1)) == sin(q) * cos(q1) + cos(q) * sin(q1));
  CHECK(normalize(cos(4 * q)) ==
        pow(pow(cos(q), 2) - pow(sin(q), 2), 2) - 4 * pow(sin(q), 2) * pow(cos(q), 2));
}

// ---------------------------------------------------------------- rule fuzz

TEST_CASE("every rule row is an identity: both sides agree at random points", "[simplify][rules]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
  std::mt19937 rng(7);
  std::size_t rows = 0;
  for (const auto& table : all_rule_tables()) {
    for (const Rule& r : table.rules) {
      ++rows;
      std::vector<Expr> wilds;
      std::unordered_set<std::uint32_t> seen;
      collect_symbols(r.pattern, &wilds, &seen);
      int checked = 0;
      for (unsigned trial = 0; trial < 60; ++trial) {
        symdyn::testing::RandomExpr gen(trial * 131 + static_cast<unsigned>(rows), xs);
        Match m;
        for (Expr w : wilds) {
          if (is_wildcard(w)) m.bind(w, trial % 3 == 0 ? gen.leaf() : gen(3));
        }
        if (r.condition && !r.condition(m)) continue;
        Expr lhs, rhs;
        try {
          lhs = instantiate(r.pattern, m);
          rhs = instantiate(r.replacement, m);
        } catch (const DomainError&) {
          continue;  // a number outside asin's or acos's domain: the identity holds only inside
        }
        INFO("rule '" << r.name << "' (" << table.name << "): " << lhs << "  vs  " << rhs);
        CHECK(same_values(lhs, rhs, rng, 3));
        ++checked;
      }
      INFO("rule '" << r.name << "'");
      CHECK(checked > 10);
    }
  }
  CHECK(rows >= 20);
}

TEST_CASE("every rule row matches its own pattern instantiated with fresh symbols",
          "[simplify][rules]") {
  Context ctx;
  Context::Scope scope(ctx);
  std::mt19937 rng(11);
  for (const auto& table : all_rule_tables()) {
    for (const Rule& r : table.rules) {
      std::vector<Expr> wilds;
      std::unordered_set<std::uint32_t> seen;
      collect_symbols(r.pattern, &wilds, &seen);
      Match m;
      int k = 0;
      for (Expr w : wilds) {
        if (!is_wildcard(w)) continue;
        // Cofactors and rests get a product or sum, so the match has to find them.
        const Expr s = symbol(fmt::format("s{}", k++), SymbolKind::Parameter);
        const Expr t = symbol(fmt::format("t{}", k++), SymbolKind::Parameter);
        const char c = w.name()[1];
        m.bind(w, c == 'a' || c == 'b' ? 3 * s * t : (c == 'R' ? s + t : s));
      }
      const Expr target = instantiate(r.pattern, m);
      INFO("rule '" << r.name << "': target " << target);
      const auto found = find_matches(r.pattern, target);
      REQUIRE_FALSE(found.empty());
      bool agrees = true;
      for (const Match& f : found) {
        if (r.condition && !r.condition(f)) continue;
        agrees = agrees && same_values(instantiate(r.replacement, f), target, rng, 2);
      }
      CHECK(agrees);
    }
  }
}

// ---------------------------------------------------------------- named identities

TEST_CASE("cos q0 cos q1 - sin q0 sin q1 = cos(q0 + q1)", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q0 = symbol("q0", SymbolKind::Variable), q1 = symbol("q1", SymbolKind::Variable);
  const Expr e = cos(q0) * cos(q1) - sin(q0) * sin(q1);
  CHECK(simplify(e) == cos(q0 + q1));
  CHECK(simplify(-e) == -cos(q0 + q1));
  CHECK(simplify(sin(q0) * cos(q1) - cos(q0) * sin(q1)) == sin(q0 - q1));
  CHECK(simplify(cos(q0) * cos(q1) + sin(q0) * sin(q1)) == cos(q0 - q1));
  CHECK(simplify(sin(q0) * cos(q1) + cos(q0) * sin(q1)) == sin(q0 + q1));
}

TEST_CASE("double pendulum: x of rod 2's centre contracts to cos(q0 + q1)",
          "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q0 = symbol("q0", SymbolKind::Variable), q1 = symbol("q1", SymbolKind::Variable);
  const Expr l1 = symbol("l1", SymbolKind::Parameter), l2 = symbol("l2", SymbolKind::Parameter);
  const Expr e = l1 * cos(q0) + l2 / 2 * (cos(q0) * cos(q1) - sin(q0) * sin(q1));
  const Expr expected = l1 * cos(q0) + l2 / 2 * cos(q0 + q1);
  CHECK(simplify(e) == expected);
  // The same with the factor distributed.
  CHECK(simplify(expand(e)) == expected);
  CHECK(operation_cost(expected) < operation_cost(e));
}

TEST_CASE("sin^2 + cos^2 = 1, scaled and within a larger sum", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q"), y = symbol("y"), z = symbol("z");
  CHECK(simplify(pow(sin(q), 2) + pow(cos(q), 2)) == Expr(1));
  CHECK(simplify(3 * y * pow(sin(q), 2) + 3 * y * pow(cos(q), 2) + z) == 3 * y + z);
  CHECK(simplify(pow(sin(q + y), 2) + pow(cos(q + y), 2)) == Expr(1));
  // Different scales: a sin^2 + b cos^2 = a + (b - a) cos^2.
  const Expr e = 3 * y * pow(sin(q), 2) + 5 * y * pow(cos(q), 2);
  const Expr s = simplify(e);
  std::mt19937 rng(3);
  CHECK(same_values(s, e, rng));
  CHECK(operation_cost(s) <= operation_cost(3 * y + 2 * y * pow(cos(q), 2)));
  Rewriter contract(contracting_trig_rules(), Strategy::Improve);
  CHECK(contract(e) == 3 * y + 2 * y * pow(cos(q), 2));
  CHECK(simplify(1 - pow(sin(q), 2)) == pow(cos(q), 2));
  CHECK(simplify(y - y * pow(cos(q), 2)) == y * pow(sin(q), 2));
}

TEST_CASE("nested sin^2 + cos^2 = 1, factored and expanded", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a"), b = symbol("b");
  const Expr nested = pow(sin(a), 2) * (pow(sin(b), 2) + pow(cos(b), 2)) + pow(cos(a), 2);
  CHECK(simplify(nested) == Expr(1));
  const Expr expanded =
      pow(sin(a), 2) * pow(sin(b), 2) + pow(sin(a), 2) * pow(cos(b), 2) + pow(cos(a), 2);
  CHECK(expanded == expand(nested));
  CHECK(simplify(expanded) == Expr(1));
}

TEST_CASE("double angles both ways", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q"), y = symbol("y");
  CHECK(simplify(2 * sin(q) * cos(q)) == sin(2 * q));
  CHECK(simplify(y * pow(cos(q), 2) - y * pow(sin(q), 2)) == y * cos(2 * q));
  CHECK(simplify(2 * pow(cos(q), 2) - 1) == cos(2 * q));
  CHECK(simplify(1 - 2 * pow(sin(q), 2)) == cos(2 * q));
  // Back: cos 2q - cos^2 q + sin^2 q is zero through the expansion of cos 2q.
  CHECK(simplify(cos(2 * q) - pow(cos(q), 2) + pow(sin(q), 2)) == Expr(0));
  CHECK(simplify(sin(2 * q) - 2 * sin(q) * cos(q)) == Expr(0));
}

// A node that still holds asin, acos or atan2 once its operands are simplified
// is contracted but not expanded (simplify.hpp); its operands are simplified
// as usual, so the algebraic rules still reach through.
TEST_CASE("sums holding inverse trigonometric functions still take the algebraic rules",
          "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q"), x = symbol("x");
  const Expr rotated = cos(q) * cos(asin(x)) - sin(q) * sin(asin(x));
  CHECK(simplify(rotated) == sqrt(1 - x * x) * cos(q) - x * sin(q));
  // cos(asin x) = sqrt(1 - x²) first; the sum, free of asin, then expands to x².
  const Expr pythagoras = (sin(q) + cos(asin(x))) * (sin(q) - cos(asin(x))) + pow(cos(q), 2);
  CHECK(simplify(pythagoras) == x * x);
}

TEST_CASE("products to sums (tlin) when that is shorter", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr p = symbol("p"), q = symbol("q");
  // sin p cos q + cos p sin q ... plus a product that only the linearized form cancels.
  const Expr e = 2 * sin(p) * cos(q) - sin(p + q) - sin(p - q);
  CHECK(simplify(e) == Expr(0));
  const Expr f = 2 * cos(p) * cos(q) - cos(p - q);
  CHECK(simplify(f) == cos(p + q));
}

TEST_CASE("angular velocity of Trotz(q0) Trotz(q1) is qd0 + qd1", "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> q{symbol("q0", SymbolKind::Variable), symbol("q1", SymbolKind::Variable)};
  const std::vector<Expr> qd{symbol("qd0", SymbolKind::Rate), symbol("qd1", SymbolKind::Rate)};
  const auto w = angular_velocity(product(rot_z(q[0]), rot_z(q[1])), q, qd);
  CHECK(simplify(w[0]) == Expr(0));
  CHECK(simplify(w[1]) == Expr(0));
  CHECK(simplify(w[2]) == qd[0] + qd[1]);
}

TEST_CASE("angular velocity of Trotz(q0) Troty(q1) Trotx(q2) reaches the closed form",
          "[simplify][identity]") {
  Context ctx;
  Context::Scope scope(ctx);
  const std::vector<Expr> q{symbol("q0", SymbolKind::Variable), symbol("q1", SymbolKind::Variable),
                            symbol("q2", SymbolKind::Variable)};
  const std::vector<Expr> qd{symbol("qd0", SymbolKind::Rate), symbol("qd1", SymbolKind::Rate),
                             symbol("qd2", SymbolKind::Rate)};
  const Mat3 r = product(product(rot_z(q[0]), rot_y(q[1])), rot_x(q[2]));
  const auto w = angular_velocity(r, q, qd);
  // ZYX Euler angles: w = qd0 e_z + qd1 Rz(q0) e_y + qd2 Rz(q0) Ry(q1) e_x.
  const std::array<Expr, 3> closed{-sin(q[0]) * qd[1] + cos(q[0]) * cos(q[1]) * qd[2],
                                   cos(q[0]) * qd[1] + sin(q[0]) * cos(q[1]) * qd[2],
                                   qd[0] - sin(q[1]) * qd[2]};
  std::mt19937 rng(5);
  Simplifier simplifier;
  for (int i = 0; i < 3; ++i) {
    const Expr s = simplifier(w[i]);
    INFO("w[" << i << "] = " << s << "   (cost " << operation_cost(w[i]) << " -> "
              << operation_cost(s) << ")");
    CHECK(same_values(s, closed[i], rng));
    CHECK(s == closed[i]);
  }
  // Together, sharing sin q0, cos q0, cos q1.
  const auto all = simplifier(std::span<const Expr>(w));
  CHECK(operation_cost(all) == operation_cost(closed));
}

// ---------------------------------------------------------------- properties

TEST_CASE("simplify keeps values, never raises the cost, and is idempotent",
          "[simplify][property]") {
  // Products of two trigonometric sums take ~60 ms each (two simplify calls):
  // every 10th trigonometric case is one. Debug (sanitizer) builds, 20 to 50
  // times slower, run a twentieth: they look for memory errors, not coverage.
#ifdef NDEBUG
  const unsigned general_cases = 1800;
  const unsigned trig_cases = 1300;
#else
  const unsigned general_cases = 90;
  const unsigned trig_cases = 65;
#endif
  std::mt19937 rng(2024);
  int changed = 0;
  int total = 0;
  auto check_one = [&](Expr e) {
    const Expr s = simplify(e);
    INFO("input  " << e << "\noutput " << s);
    REQUIRE(same_values(s, e, rng, 3));
    REQUIRE(operation_cost(s) <= operation_cost(e));
    REQUIRE(simplify(s) == s);
    changed += s != e;
    ++total;
  };
  for (unsigned seed = 0; seed < general_cases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
    symdyn::testing::RandomExpr gen(seed, xs);
    check_one(gen(4));
  }
  for (unsigned seed = 0; seed < trig_cases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> angles{symbol("q0"), symbol("q1"), symbol("q2")};
    const std::vector<Expr> factors{symbol("l"), symbol("m"), symbol("qd0")};
    std::mt19937 local(seed);
    Expr e = random_trig(local, angles, factors);
    if (seed % 10 == 0)
      e = e * random_trig(local, angles, factors);  // a product of sums: expand pays
    check_one(e);
  }
  CHECK(total == static_cast<int>(general_cases + trig_cases));
  CHECK(changed > total / 10);  // simplify does something on this workload
}
