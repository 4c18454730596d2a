// Bad input to the builder API and Model::validate(): one case per mistake,
// each checking that the message names the culprit (docs/errors.md).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include <symdyn/model/model.hpp>

using namespace symdyn::model;
using Catch::Matchers::Contains;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A valid one-body pendulum, the base every case spoils in one way.
Model pendulum(std::string name = "pendulum") {
  Model m(std::move(name));
  const Expr q0 = m.coordinate("q0");
  m.body("rod").mass(1.0).inertia(0.001, 0.08, 0.08).motion(Trotz(q0) * Tdisp(0.5, 0, 0));
  m.gravity(0, -9.81, 0);
  return m;
}

Expr q0_of(const Model& m) {
  return m.coordinates().front().q;
}

// The pendulum with a second body of the given mass and principal moments.
Model with_body(Scalar mass, Scalar ixx, Scalar iyy, Scalar izz) {
  Model m = pendulum();
  m.body("b").mass(mass).inertia(ixx, iyy, izz).motion(Trotz(q0_of(m)) * Tdisp(1, 0, 0));
  return m;
}

}  // namespace

TEST_CASE("the base of the bad-input cases is valid", "[bad_input]") {
  CHECK_NOTHROW(pendulum().validate());
  CHECK_NOTHROW(with_body(2.0, 0.1, 0.1, 0.1).validate());
}

TEST_CASE("builder: names that are not identifiers are refused at the call", "[bad_input]") {
  CHECK_THROWS_WITH(Model("2nd"), "model name '2nd' is not a C++ identifier (starts with a digit)");
  CHECK_THROWS_WITH(Model(""), "model name '' is empty");
  Model m = pendulum();
  CHECK_THROWS_WITH(m.coordinate("q-1"),
                    "coordinate name 'q-1' is not a C++ identifier (character '-' at 1)");
  CHECK_THROWS_WITH(m.parameter("l 1", 1.0),
                    "parameter name 'l 1' is not a C++ identifier (character ' ' at 1)");
  CHECK_THROWS_WITH(m.dependent("", Expr(1)), "dependent parameter name '' is empty");
  CHECK_THROWS_WITH(m.body("arm.2"),
                    "body name 'arm.2' is not a C++ identifier (character '.' at 3)");
}

TEST_CASE("builder: a coordinate may not take the name of time", "[bad_input]") {
  Model m = pendulum();
  CHECK_THROWS_WITH(m.coordinate("t"), Contains("'t'"));
}

TEST_CASE("builder: a non-finite number names its body, quantity or gravity", "[bad_input]") {
  Model m = pendulum();
  CHECK_THROWS_WITH(m.parameter("l1", kNaN), "parameter 'l1' = nan is not finite");
  CHECK_THROWS_WITH(m.parameter("l2", kInf, true), "parameter 'l2' = inf is not finite");
  CHECK_THROWS_WITH(m.body("a").mass(kNaN), "body 'a': mass is not finite (nan)");
  CHECK_THROWS_WITH(m.body("b").mass(-kInf), "body 'b': mass is not finite (-inf)");
  CHECK_THROWS_WITH(m.body("c").inertia(0.1, kNaN, 0.1),
                    "body 'c': inertia Iyy is not finite (nan)");
  CHECK_THROWS_WITH(m.body("d").inertia(Expr(0.1), 0.1, -kInf),
                    "body 'd': inertia Izz is not finite (-inf)");
  CHECK_THROWS_WITH(m.gravity(0, kNaN, 0), "gravity y is not finite (nan)");
  CHECK_THROWS_WITH(m.gravity(0, 0, kInf), "gravity z is not finite (inf)");
}

TEST_CASE("builder: gravity may use only declared symbols", "[bad_input]") {
  Model m = pendulum();
  const Expr g = symbol("g", symdyn::symbolic::SymbolKind::Parameter);
  CHECK_THROWS_WITH(m.gravity(0, g, 0),
                    Contains("gravity uses 'g', which is not declared in model 'pendulum'"));
}

TEST_CASE("validate: masses and inertias the runtime refuses", "[bad_input]") {
  CHECK_THROWS_WITH(with_body(0.0, 0.1, 0.1, 0.1).validate(), "body 'b': mass 0 is not positive");
  CHECK_THROWS_WITH(with_body(-2.0, 0.1, 0.1, 0.1).validate(), "body 'b': mass -2 is not positive");
  CHECK_THROWS_WITH(with_body(1.0, 0.0, 0.1, 0.1).validate(),
                    "body 'b': inertia is not positive definite (principal moments 0, 0.1, 0.1)");
  CHECK_THROWS_WITH(with_body(1.0, 0.1, 0.1, 0.2001).validate(),
                    Contains("body 'b': inertia violates the triangle inequality"));
  // A thin disc is exactly at the triangle limit: the runtime accepts it.
  CHECK_NOTHROW(with_body(1.0, 0.1, 0.1, 0.2).validate());
}

TEST_CASE("validate: an asymmetric inertia beyond the runtime's tolerance", "[bad_input]") {
  Model m = pendulum();
  m.body("b")
      .mass(1.0)
      .inertia(Mat3{Expr(0.2), Expr(1e-6), Expr(0), Expr(0), Expr(0.2), Expr(0), Expr(0), Expr(0),
                    Expr(0.2)})
      .motion(Tdisp(1, 0, 0) * Trotz(q0_of(m)));
  CHECK_THROWS_WITH(m.validate(), "body 'b': inertia is not symmetric (I01 = 1e-06 but I10 = 0)");
}

TEST_CASE("validate: a run-time parameter's default must give a physical body", "[bad_input]") {
  Model m = pendulum();
  const Expr mb = m.parameter("mb", -3.0, true);
  m.body("b").mass(mb).inertia(0.1, 0.1, 0.1).motion(Trotz(q0_of(m)));
  CHECK_THROWS_WITH(m.validate(), "body 'b': mass -3 is not positive");
  Model ok = pendulum();
  ok.body("b").mass(ok.parameter("mb", 3.0, true)).inertia(0.1, 0.1, 0.1).motion(Trotz(q0_of(ok)));
  CHECK_NOTHROW(ok.validate());
}

TEST_CASE("validate: a mass or inertia depending on the motion names the body and the symbol",
          "[bad_input]") {
  SECTION("coordinate") {
    Model m = pendulum();
    m.body("b").mass(1 + q0_of(m) * q0_of(m)).inertia(0.1, 0.1, 0.1).motion(Trotz(q0_of(m)));
    CHECK_THROWS_WITH(m.validate(),
                      "body 'b': mass depends on coordinate 'q0'; a mass or inertia may use only "
                      "constants and run-time parameters");
  }
  SECTION("time") {
    Model m = pendulum();
    m.body("b").mass(1.0).inertia(0.1, 0.1 + m.time() * m.time(), 0.1).motion(Trotz(q0_of(m)));
    CHECK_THROWS_WITH(m.validate(), Contains("body 'b': inertia I11 depends on time 't'"));
  }
  SECTION("dependent parameter") {
    Model m = pendulum();
    const Expr alpha = m.dependent("alpha", cos(q0_of(m)));
    m.body("b").mass(2 + alpha).inertia(0.1, 0.1, 0.1).motion(Trotz(q0_of(m)));
    CHECK_THROWS_WITH(m.validate(),
                      Contains("body 'b': mass depends on dependent parameter 'alpha'"));
  }
}

TEST_CASE("validate: gravity must be a number", "[bad_input]") {
  SECTION("run-time parameter") {
    Model m = pendulum();
    const Expr g = m.parameter("g", 9.81, true);
    m.gravity(0, -g, 0);
    CHECK_THROWS_WITH(m.validate(), Contains("gravity y: '") &&
                                        Contains("depends on run-time parameter 'g'; gravity "
                                                 "must be a number"));
  }
  SECTION("coordinate") {
    Model m = pendulum();
    m.gravity(q0_of(m), 0, 0);
    CHECK_THROWS_WITH(m.validate(),
                      "gravity x: 'q0' depends on coordinate 'q0'; gravity must be a number");
  }
}

TEST_CASE("validate: a coordinate that moves no body is named", "[bad_input]") {
  SECTION("used nowhere") {
    Model m = pendulum();
    m.coordinate("q1");
    CHECK_THROWS_WITH(m.validate(),
                      "coordinate 'q1' moves no body: no body's position or rotation depends on it "
                      "(its mass matrix row would be zero)");
  }
  SECTION("used only by a dependent parameter no motion uses") {
    Model m = pendulum();
    const Expr q1 = m.coordinate("q1");
    m.dependent("unused", sin(q1));
    CHECK_THROWS_WITH(m.validate(), Contains("coordinate 'q1' moves no body"));
  }
  SECTION("used through a chain of dependent parameters: accepted") {
    Model m = pendulum();
    const Expr q1 = m.coordinate("q1");
    const Expr a = m.dependent("a", sin(q1));
    const Expr b = m.dependent("b", 2 * a);
    m.body("slider").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(b, 0, 0));
    CHECK_NOTHROW(m.validate());
  }
}

TEST_CASE("validate: a dependent parameter out of its domain at the initial configuration",
          "[bad_input]") {
  SECTION("asin of run-time parameters") {
    Model m = pendulum();
    const Expr l1 = m.parameter("l1", 0.5, true), l2 = m.parameter("l2", 0.2, true);
    m.body("b")
        .mass(1.0)
        .inertia(0.1, 0.1, 0.1)
        .motion(Trotz(m.dependent("alpha", asin(l1 / l2) + q0_of(m))));
    CHECK_THROWS_WITH(m.validate(),
                      "dependent parameter 'alpha': asin(2.5) is not defined at the initial "
                      "configuration (t = 0, coordinates at their initial values)");
  }
  SECTION("acos of a coordinate") {
    Model m = pendulum();
    m.initial(q0_of(m), 2.0);
    m.body("b").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Trotz(m.dependent("beta", acos(q0_of(m)))));
    CHECK_THROWS_WITH(m.validate(), Contains("dependent parameter 'beta': acos(2) is not defined"));
  }
  SECTION("sqrt") {
    Model m = pendulum();
    m.body("b")
        .mass(1.0)
        .inertia(0.1, 0.1, 0.1)
        .motion(Tdisp(m.dependent("r", sqrt(q0_of(m) - 1)), 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("dependent parameter 'r': sqrt(-1) is not defined"));
  }
  SECTION("log at a later dependent parameter") {
    Model m = pendulum();
    const Expr c = m.dependent("c", cos(q0_of(m)) - 1);  // 0 at q0 = 0
    m.body("b")
        .mass(1.0)
        .inertia(0.1, 0.1, 0.1)
        .motion(Tdisp(m.dependent("d", log(c + q0_of(m))), 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("dependent parameter 'd': log(0) is not defined"));
  }
}

TEST_CASE(
    "validate: an inlined motion out of its domain at the initial configuration names the body",
    "[bad_input]") {
  Model m = pendulum();
  m.inline_dependents(true);
  const Expr l = m.parameter("l", 3.0, true);
  m.body("slider")
      .mass(1.0)
      .inertia(0.1, 0.1, 0.1)
      .motion(Tdisp(m.dependent("x", acos(l * cos(q0_of(m)))), 0, 0));
  CHECK_THROWS_WITH(
      m.validate(),
      "body 'slider' motion: acos(3) is not defined at the initial configuration (t = 0, "
      "coordinates at their initial values)");
}

TEST_CASE("a constant out of its domain while building names the model and variant",
          "[bad_input]") {
  const Definition d{
      "toy", {"only"}, [](Model& m, std::string_view) { m.parameter("x", 1.0) + asin(Expr(2.0)); }};
  CHECK_THROWS_AS(d.make(), ModelError);
  CHECK_THROWS_WITH(d.make(), Contains("model 'toy' variant 'only': asin(2") &&
                                  Contains("outside the function's real domain"));
}
