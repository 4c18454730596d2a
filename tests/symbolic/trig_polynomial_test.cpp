// The normal form modulo sin² + cos² = 1 (trig_polynomial.hpp) and the
// closed forms of sin, cos and tan of asin, acos and atan (construct.cpp):
// exact results on known identities, and values preserved at random points.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/trig_polynomial.hpp>

using namespace symdyn::symbolic;

namespace {

double value(Expr e, const Bindings<double>& at) {
  return evaluate(e, at);
}

bool close(double a, double b) {
  return std::abs(a - b) <= 1e-12 * std::max({1.0, std::abs(a), std::abs(b)});
}

// A random polynomial in sines and cosines of `angles` (and of their sums)
// with small integer or inexact coefficients and factors among `others`.
Expr random_trig_polynomial(std::span<const Expr> angles, std::span<const Expr> others) {
  const int n_terms = *rc::gen::inRange(1, 6);
  Expr sum = 0;
  for (int t = 0; t < n_terms; ++t) {
    // Generated values are indices, never expressions: rapidcheck replays
    // values while shrinking, and each run has its own Context.
    const std::vector<Expr> coefficients{1, -2, 3, 0.7, rational(1, 3)};
    Expr term = coefficients[*rc::gen::inRange<std::size_t>(0, coefficients.size())];
    const int n_factors = *rc::gen::inRange(1, 4);
    for (int f = 0; f < n_factors; ++f) {
      Expr angle = angles[*rc::gen::inRange<std::size_t>(0, angles.size())];
      if (*rc::gen::inRange(0, 4) == 0)
        angle = angle + angles[*rc::gen::inRange<std::size_t>(0, angles.size())];
      Expr g = *rc::gen::arbitrary<bool>() ? sin(angle) : cos(angle);
      const int power = *rc::gen::inRange(1, 4);
      term = term * pow(g, power);
    }
    if (*rc::gen::arbitrary<bool>())
      term = term * others[*rc::gen::inRange<std::size_t>(0, others.size())];
    sum = sum + term;
  }
  // A square of a sum, as a rotation's column norm: the expansion is needed.
  if (*rc::gen::arbitrary<bool>()) sum = pow(sum, 2) + sum;
  return sum;
}

}  // namespace

TEST_CASE("sums of squares of sines and cosines collect to constants",
          "[simplify][trig_polynomial]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a", SymbolKind::Variable), b = symbol("b", SymbolKind::Variable),
             c = symbol("c", SymbolKind::Variable), m = symbol("m", SymbolKind::Parameter);
  TrigPolynomialForm form;
  CHECK(form(pow(sin(a), 2) + pow(cos(a), 2)) == Expr(1));
  CHECK(form(3 * pow(sin(a), 2) + 3 * pow(cos(a), 2)) == Expr(3));
  // The squared norm of a rotation's column: Rz(a)·Ry(b)·Rx(c), first column.
  const Expr x = cos(a) * cos(b), y = sin(a) * cos(b), z = -sin(b);
  CHECK(form(186 * (x * x + y * y + z * z)) == Expr(186));
  // Its second column, with a parameter as the coefficient.
  const Expr x2 = cos(a) * sin(b) * sin(c) - sin(a) * cos(c),
             y2 = sin(a) * sin(b) * sin(c) + cos(a) * cos(c), z2 = cos(b) * sin(c);
  CHECK(form(m * (x2 * x2 + y2 * y2 + z2 * z2)) == m);
  // Two columns are orthogonal: their dot product is exactly 0.
  CHECK(form(x * x2 + y * y2 + z * z2) == Expr(0));
  // With coefficients: 5/12 + (1/2 + cos b)² + sin² b = 5/3 + cos b.
  CHECK(form(rational(5, 12) + pow(rational(1, 2) + cos(b), 2) + pow(sin(b), 2)) ==
        rational(5, 3) + cos(b));
  // Inexact coefficients that cancel to rounding cancel.
  CHECK(form(0.1 * 3 * pow(sin(a), 2) + 0.3 * pow(cos(a), 2) - 0.30000000000000004) == Expr(0));
}

TEST_CASE("definitions are seen through", "[simplify][trig_polynomial]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a", SymbolKind::Variable), b = symbol("b", SymbolKind::Variable);
  const Expr u = symbol("u", SymbolKind::Intermediate), v = symbol("v", SymbolKind::Intermediate);
  const std::vector<Definition> defs{{u, cos(a) * cos(b)}, {v, sin(a) * cos(b)}};
  TrigPolynomialForm form(defs);
  CHECK(form(2 * u * u + 2 * v * v + 2 * pow(sin(b), 2)) == Expr(2));

  // reduce_pythagorean: the output becomes the constant, the definitions stay.
  const Expr w = symbol("w", SymbolKind::Intermediate);
  const std::vector<Definition> own{{w, u * u + v * v}};
  const PythagoreanReduction r =
      reduce_pythagorean(std::vector<Expr>{w + pow(sin(b), 2), u}, own, defs);
  CHECK(r.outputs[0] == Expr(1));
  CHECK(r.outputs[1] == u);
  REQUIRE(r.definitions.size() == 1);
  CHECK(r.definitions[0].value == pow(cos(b), 2));
}

TEST_CASE("reduce_pythagorean: a sin/cos pair is one call", "[simplify][trig_polynomial]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a", SymbolKind::Variable);
  // t is sin(2a): the first output is shorter as 1 - cos(2a)^2 + sin(2a), whose
  // cos(2a) comes with sin(2a) in one sincos. Counted apart, it would look costlier.
  const Expr s2 = sin(2 * a), t = pow(sin(a), 2) * s2 + s2 * pow(cos(a), 2);
  const std::vector<Expr> outputs{t + pow(t, 2), sin(a) * cos(a) + s2};
  const PythagoreanReduction r = reduce_pythagorean(outputs, {});
  CHECK(r.outputs[0] == 1 - pow(cos(2 * a), 2) + s2);
  CHECK(r.outputs[1] == outputs[1]);
  CHECK(fused_operation_cost(r.outputs) < fused_operation_cost(outputs));
  CHECK(operation_cost(r.outputs) > operation_cost(outputs));
}

TEST_CASE("fused_operation_cost counts sin and cos of one argument once", "[simplify][cost]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a", SymbolKind::Variable), b = symbol("b", SymbolKind::Variable);
  const std::vector<Expr> pair{sin(a) + cos(a)}, apart{sin(a) + cos(b)};
  CHECK(operation_cost(pair) == operation_cost(apart));
  CHECK(fused_operation_cost(pair) ==
        fused_operation_cost(apart) - operation_cost(cos(b)) + operation_cost(b));
  CHECK(fused_operation_cost(std::vector<Expr>{sin(a), sin(a) * cos(a)}) ==
        operation_cost(sin(a)) + 1);
}

TEST_CASE("reduce_pythagorean keeps what is not shorter", "[simplify][trig_polynomial]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr a = symbol("a", SymbolKind::Variable), b = symbol("b", SymbolKind::Variable);
  // Expanded, (cos a + cos b)^3 is longer: kept.
  const Expr e = pow(cos(a) + cos(b), 3);
  CHECK(reduce_pythagorean(std::vector<Expr>{e}, {}).outputs[0] == e);
}

TEST_CASE("the normal form preserves values", "[simplify][trig_polynomial][random]") {
  rc::prop("form(e) == e at random points", [] {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> angles{symbol("a", SymbolKind::Variable),
                                   symbol("b", SymbolKind::Variable),
                                   symbol("c", SymbolKind::Variable)};
    const std::vector<Expr> others{symbol("x", SymbolKind::Rate),
                                   symbol("y", SymbolKind::Parameter)};
    const Expr e = random_trig_polynomial(angles, others);
    const std::size_t limit = *rc::gen::element<std::size_t>(4, 32, 256);
    TrigPolynomialForm form({}, limit);
    const Expr f = form(e);
    RC_LOG() << e << "  ->  " << f << "\n";
    std::mt19937 rng(*rc::gen::arbitrary<unsigned>());
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 4; ++k) {
      Bindings<double> at;
      for (Expr s : angles) at[s] = u(rng);
      for (Expr s : others) at[s] = u(rng);
      const double ve = value(e, at), vf = value(f, at);
      RC_ASSERT(std::abs(ve - vf) <= 1e-11 * std::max(1.0, std::abs(ve)));
    }
    // Idempotent: the normal form of a normal form (same limit) is itself.
    TrigPolynomialForm again({}, limit);
    RC_ASSERT(again(f) == f);
  });
  rc::prop("reduce_pythagorean makes no value costlier and keeps values", [] {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> angles{symbol("a", SymbolKind::Variable),
                                   symbol("b", SymbolKind::Variable)};
    const std::vector<Expr> others{symbol("x", SymbolKind::Rate)};
    const std::vector<Expr> outputs{random_trig_polynomial(angles, others),
                                    random_trig_polynomial(angles, others)};
    const PythagoreanReduction r = reduce_pythagorean(outputs, {});
    // Each alone, a sin/cos pair as one call (weighed apart, see trig_polynomial.hpp).
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      RC_ASSERT(fused_operation_cost(std::span(&r.outputs[i], 1)) <=
                fused_operation_cost(std::span(&outputs[i], 1)));
    }
    Bindings<double> at{{angles[0], 0.3}, {angles[1], -1.1}, {others[0], 0.7}};
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      const double ve = value(outputs[i], at);
      RC_ASSERT(std::abs(ve - value(r.outputs[i], at)) <= 1e-11 * std::max(1.0, std::abs(ve)));
    }
  });
}

TEST_CASE("sin, cos and tan of asin, acos and atan in closed form",
          "[construct][trig_polynomial]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr u = symbol("u");
  CHECK(sin(asin(u)) == u);
  CHECK(cos(acos(u)) == u);
  CHECK(tan(atan(u)) == u);
  CHECK(cos(asin(u)) == sqrt(1 - u * u));
  CHECK(sin(acos(u)) == sqrt(1 - u * u));
  CHECK(cos(atan(u)) == 1 / sqrt(1 + u * u));
  CHECK(sin(atan(u)) == u / sqrt(1 + u * u));
  CHECK(tan(asin(u)) == u / sqrt(1 - u * u));
  CHECK(tan(acos(u)) == sqrt(1 - u * u) / u);
  // Through the odd symmetry: sin(asin(-u)) = -u, cos(asin(-u)) = cos(asin u).
  CHECK(sin(asin(-u)) == -u);
  CHECK(cos(asin(-u)) == sqrt(1 - u * u));
  // No call is left.
  CHECK(operation_cost(cos(asin(u))) < info(Kind::Cos).cost);
}

TEST_CASE("the closed forms of sin, cos, tan of inverse functions keep values",
          "[construct][random]") {
  rc::prop("inside the domain: asin's and acos's argument in [-1, 1]", [] {
    Context ctx;
    Context::Scope scope(ctx);
    const Expr u = symbol("u");
    const Expr x = symbol("x");
    // u's value in [-1, 1]; the argument a polynomial of u, scaled into [-1, 1].
    const double uv = *rc::gen::inRange(-1000000, 1000001) / 1e6;
    const double xv = *rc::gen::inRange(-3000000, 3000001) / 1e6;
    const std::vector<Expr> args{u, -u, u * u, u * u * u, (u + u * u) / 2};
    const Expr arg = args[*rc::gen::inRange<std::size_t>(0, args.size())];
    const Bindings<double> at{{u, uv}, {x, xv}};
    const double a = value(arg, at);
    struct Case {
      Expr built;
      double expected;
    };
    const std::vector<Case> cases{
        {sin(asin(arg)), std::sin(std::asin(a))},
        {cos(asin(arg)), std::cos(std::asin(a))},
        {sin(acos(arg)), std::sin(std::acos(a))},
        {cos(acos(arg)), std::cos(std::acos(a))},
        {sin(atan(x * arg)), std::sin(std::atan(xv * a))},
        {cos(atan(x * arg)), std::cos(std::atan(xv * a))},
        {tan(atan(x * arg)), std::tan(std::atan(xv * a))},
        {x * cos(asin(arg)), xv * std::cos(std::asin(a))},
    };
    for (const Case& c : cases) {
      RC_LOG() << c.built << " at u = " << uv << ", x = " << xv << "\n";
      RC_ASSERT(close(value(c.built, at), c.expected));
    }
    if (std::abs(a) < 0.999) {  // tan(asin a) and tan(acos a) away from their poles
      RC_ASSERT(std::abs(value(tan(asin(arg)), at) - std::tan(std::asin(a))) <=
                1e-9 * (1 + std::abs(std::tan(std::asin(a)))));
    }
    if (std::abs(a) > 1e-3) {
      RC_ASSERT(std::abs(value(tan(acos(arg)), at) - std::tan(std::acos(a))) <=
                1e-9 * (1 + std::abs(std::tan(std::acos(a)))));
    }
  });
}
