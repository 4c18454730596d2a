#include <catch2/catch.hpp>

#include "symbolic/eval.hpp"
#include "symbolic/expr.hpp"
#include "symbolic/print.hpp"

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
