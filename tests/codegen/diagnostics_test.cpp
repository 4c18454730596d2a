// The cold diagnostics the generator emits (docs/emitted_interface.md): the
// dependent parameters' names, their operations of restricted domain with
// their arguments, and the bodies' angle sequences. Values against closed
// forms; detection against motions written by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "slider_crank_dependent.hpp"
#include "slider_crank_inline.hpp"
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/diagnostics.hpp>

using namespace symdyn;
using Catch::Matchers::Contains;

TEST_CASE("emitted slider-crank: its dependent parameters named, asin's argument l1·sin(crank)/l2",
          "[codegen][diagnostics]") {
  using G = symdyn_generated::slider_crank_dependent;
  STATIC_REQUIRE(G::ndomain == 1);
  CHECK(std::string(G::dependent_names[0]) == "alpha");
  CHECK(std::string(G::dependent_names[1]) == "slider_position");
  CHECK(std::string(G::domain_dependents[0]) == "alpha");
  CHECK(std::string(G::domain_functions[0]) == "asin");
  for (double q : {-2.0, 0.3, 1.4}) {
    double arguments[3] = {};
    G::domain_arguments(0.0, &q, nullptr, arguments);
    CHECK(arguments[0] == Approx(0.1 * std::sin(q) / 0.3).epsilon(1e-15));
    CHECK(arguments[2] == Approx(std::abs(arguments[0])).epsilon(1e-15));  // not a sum
  }
  STATIC_REQUIRE(G::nangle_sequences == 0);
}

// Inlined, x = l1·cos(crank) + l2·cos(alpha) (slider_position) holds cos(asin(u)) =
// sqrt(1 - u²) (expr.hpp): x's square root is checked too, after alpha's asin.
TEST_CASE("inlined dependent parameters keep their names and checks", "[codegen][diagnostics]") {
  using G = symdyn_generated::slider_crank_inline;
  STATIC_REQUIRE(G::ndep == 0);
  STATIC_REQUIRE(G::ndomain == 2);
  CHECK(std::string(G::domain_dependents[0]) == "alpha");
  CHECK(std::string(G::domain_functions[0]) == "asin");
  CHECK(std::string(G::domain_dependents[1]) == "slider_position");
  CHECK(std::string(G::domain_functions[1]) == "sqrt");
  const double q = 0.7;
  double arguments[6] = {};
  G::domain_arguments(0.0, &q, nullptr, arguments);
  CHECK(arguments[0] == Approx(std::sin(q) / 3.0).epsilon(1e-15));
  CHECK(arguments[3] == Approx(1 - std::sin(q) * std::sin(q) / 9.0).epsilon(1e-15));
  CHECK(arguments[4] == 0.5);
  // The scale of 1 - u² is the magnitude of its terms, 1 + u².
  CHECK(arguments[5] == Approx(1 + std::sin(q) * std::sin(q) / 9.0).epsilon(1e-15));
}

namespace {

using model::Expr;

// One body rotated by `motion` of three coordinates a, b, c (and a spare d).
struct OneBody {
  model::Model m{"one"};
  Expr a = m.coordinate("a"), b = m.coordinate("b"), c = m.coordinate("c"), d = m.coordinate("d");
  std::vector<model::AngleSequence> sequences(const model::Transform& motion) {
    m.body("B").mass(1.0).inertia(1.0, 2.0, 2.5).motion(motion);
    return model::angle_sequences(m);
  }
};

}  // namespace

TEST_CASE("angle sequences: Tait-Bryan and proper Euler found, translations between them ignored",
          "[codegen][diagnostics]") {
  using namespace model;
  {
    OneBody o;
    const auto s =
        o.sequences(Tdisp(o.d, 0, 0) * Trotz(o.a) * Tdisp(0, 0, 1) * Troty(o.b) * Trotx(o.c));
    REQUIRE(s.size() == 1);
    CHECK(s[0].name() == "Z-Y-X");
    CHECK(!s[0].proper());
    CHECK(s[0].coordinates == std::array<int, 3>{0, 1, 2});
  }
  {
    OneBody o;
    const auto s = o.sequences(Trotz(o.c) * Trotx(o.b) * Trotz(o.a));
    REQUIRE(s.size() == 1);
    CHECK(s[0].name() == "Z-X-Z");
    CHECK(s[0].proper());
    CHECK(s[0].coordinates == std::array<int, 3>{2, 1, 0});
  }
}

TEST_CASE("angle sequences: none where the rotations cannot lock that way",
          "[codegen][diagnostics]") {
  using namespace model;
  OneBody twice, repeated, constant, expression, two;
  CHECK(twice.sequences(Trotz(twice.a) * Trotz(twice.b) * Trotx(twice.c))
            .empty());  // two about one axis
  CHECK(repeated.sequences(Trotz(repeated.a) * Troty(repeated.b) * Trotx(repeated.a))
            .empty());  // a coordinate twice
  CHECK(constant.sequences(Trotz(constant.a) * Troty(Expr(0.3)) * Trotx(constant.c))
            .empty());  // a constant angle
  CHECK(expression.sequences(Trotz(expression.a) * Troty(2 * expression.b) * Trotx(expression.c))
            .empty());
  CHECK(two.sequences(Trotz(two.a) * Troty(two.b)).empty());
}

TEST_CASE("domain checks: innermost first, each restricted function, dependent parameters in order",
          "[codegen][diagnostics]") {
  model::Model m("checks");
  const Expr q = m.coordinate("q");
  const Expr p = m.dependent("p", sqrt(asin(q / 2)));
  const Expr r = m.dependent(
      "r", log(p + 1) + pow(q * q + 1, model::Expr(symbolic::Number(1, 3))) + pow(p, 3));
  const auto checks = model::domain_checks(m);
  REQUIRE(checks.size() == 4);
  CHECK(checks[0].function == "asin");
  CHECK(checks[0].dependent == "p");
  CHECK(checks[1].function == "sqrt");
  CHECK(checks[1].argument == asin(q / 2));
  CHECK(checks[2].dependent == "r");
  CHECK(checks[3].dependent == "r");
  const std::string later = checks[2].function + " " + checks[3].function;
  CHECK((later == "log pow" || later == "pow log"));  // p^3 is defined everywhere: not a check
  // Each argument's scale: the magnitude of its terms, its own where it is not a sum.
  CHECK(checks[0].scale == abs(q / 2));
  CHECK(checks[1].scale == abs(asin(q / 2)));
  for (int k : {2, 3}) {
    CAPTURE(checks[k].function);
    CHECK(checks[k].scale == (checks[k].function == "log" ? abs(p) + 1 : abs(q * q) + 1));
  }
  (void)r;
}

TEST_CASE("the generator emits the angle sequences of a free body", "[codegen][diagnostics]") {
  model::Model m("free");
  const auto q = m.coordinates(6);
  m.body("frame")
      .mass(1.0)
      .inertia(1.0, 2.0, 2.5)
      .motion(model::Tdisp(q[0], q[1], q[2]) * model::Trotz(q[3]) * model::Troty(q[4]) *
              model::Trotx(q[5]));
  const codegen::GeneratedCode code = codegen::generate(m, "v", "free_v");
  CHECK_THAT(code.header, Contains("static constexpr int nangle_sequences = 1;"));
  CHECK_THAT(code.header, Contains("angle_sequence_q[3] = {3, 4, 5};"));
  CHECK_THAT(code.header, Contains("angle_sequence_axes[1] = {\"zyx\"};"));
  CHECK_THAT(code.header, Contains("static constexpr int ndomain = 0;"));
}
