#include <catch2/catch.hpp>

#include "support/random_expr.hpp"
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/print.hpp>

using namespace symdyn::symbolic;

TEST_CASE("construction canonicalizes sums and products", "[construct]") {
  Context ctx;
  Context::Scope scope(ctx);
  Expr x = symbol("x"), y = symbol("y");
  CHECK(x + y == y + x);
  CHECK(x - x == Expr(0));
  CHECK(2 * x + 3 * x == 5 * x);
  CHECK(x * x == pow(x, 2));
  CHECK(x / x == Expr(1));
  CHECK(2 * (x + y) == 2 * x + 2 * y);
  CHECK(sin(-x) == -sin(x));
  CHECK(cos(y - x) == cos(x - y));
  CHECK(sqrt(Expr(4)) == Expr(2));
  CHECK(Expr(0.5) == rational(1, 2));
  CHECK((x + y).str() == "x + y");
  CHECK((x - 2 * y).str() == "x - 2*y");
  CHECK((x / (y * sin(x))).str() == "x/(y*sin(x))");
  CHECK(to_cpp(pow(x, 2) / 2 + sqrt(y)) == "0.5*x*x + std::sqrt(y)");
}

TEST_CASE("random expressions evaluate finite and building twice gives the same node",
          "[construct]") {
  for (unsigned seed = 0; seed < 2000; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
    symdyn::testing::RandomExpr gen_a(seed, xs), gen_b(seed, xs);
    const Expr a = gen_a(5);
    const Expr b = gen_b(5);
    INFO("seed " << seed << ": " << a);
    REQUIRE(a == b);
    const auto p = gen_a.point();
    Bindings<double> at{{xs[0], p[0]}, {xs[1], p[1]}, {xs[2], p[2]}};
    CHECK(std::isfinite(evaluate(a, at)));
  }
}
