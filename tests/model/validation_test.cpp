// Every validation error of the builder API, with its message.
#include <catch2/catch.hpp>

#include <symdyn/model/model.hpp>

using namespace symdyn::model;
using Catch::Matchers::Contains;

namespace {

Model pendulum() {
  Model m("pendulum");
  const Expr q0 = m.coordinate("q0");
  m.body("rod").mass(1.0).inertia(0.001, 0.08, 0.08).motion(Trotz(q0) * Tdisp(0.5, 0, 0));
  return m;
}

}  // namespace

TEST_CASE("a valid model passes validation", "[validation]") {
  CHECK_NOTHROW(pendulum().validate());
}

TEST_CASE("duplicate names are rejected", "[validation]") {
  Model m = pendulum();
  CHECK_THROWS_WITH(m.body("rod"), Contains("body 'rod' is declared twice"));
  CHECK_THROWS_WITH(m.coordinate("q0"), Contains("coordinate 'q0' is declared twice"));
  m.dependent("p", sin(symbol("q0", symdyn::symbolic::SymbolKind::Variable)));
  CHECK_THROWS_WITH(m.dependent("p", Expr(1)),
                    Contains("dependent parameter 'p' is declared twice"));
  CHECK_THROWS_WITH(m.parameter("q0", 1.0, true), Contains("'q0'"));
}

TEST_CASE("an unknown reference body is named", "[validation]") {
  Model m = pendulum();
  m.body("arm").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0)).relative_to("forearm");
  CHECK_THROWS_WITH(m.validate(),
                    Contains("body 'arm' is relative to 'forearm', which is not a body"));
}

TEST_CASE("a cycle of relative motions is named", "[validation]") {
  Model m = pendulum();
  m.body("a").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0)).relative_to("b");
  m.body("b").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0)).relative_to("c");
  m.body("c").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0)).relative_to("a");
  CHECK_THROWS_WITH(m.validate(),
                    Contains("relative motions form a cycle") && Contains("a -> b -> c -> a"));
}

TEST_CASE("a body relative to itself is a cycle", "[validation]") {
  Model m = pendulum();
  m.body("a").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0)).relative_to("a");
  CHECK_THROWS_WITH(m.validate(), Contains("cycle: a -> a"));
}

TEST_CASE("a dependent parameter may use only earlier ones", "[validation]") {
  Model m("m");
  const Expr q0 = m.coordinate("q0");
  const Expr later = symbol("beta", symdyn::symbolic::SymbolKind::Dependent);
  CHECK_THROWS_WITH(m.dependent("alpha", q0 + later),
                    Contains("dependent parameter 'alpha' uses 'beta', which is not declared"));
  const Expr alpha = m.dependent("alpha", sin(q0));
  CHECK_NOTHROW(m.dependent("gamma", alpha * q0));
}

TEST_CASE("a motion using an undeclared symbol is named", "[validation]") {
  Model m = pendulum();
  const Expr stray = symbol("q9", symdyn::symbolic::SymbolKind::Variable);
  m.body("arm").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Trotz(stray));
  CHECK_THROWS_WITH(m.validate(), Contains("body 'arm' motion uses 'q9', which is not declared"));
}

TEST_CASE("mass and inertia must be physical", "[validation]") {
  SECTION("negative mass") {
    Model m = pendulum();
    m.body("b").mass(-1.0).inertia(0.1, 0.1, 0.1).motion(Tdisp(1, 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("body 'b': mass -1 is not positive"));
  }
  SECTION("negative principal moment") {
    Model m = pendulum();
    m.body("b").mass(1.0).inertia(0.1, -0.1, 0.1).motion(Tdisp(1, 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("body 'b': inertia is not positive definite"));
  }
  SECTION("triangle inequality") {
    Model m = pendulum();
    m.body("b").mass(1.0).inertia(0.1, 0.1, 0.3).motion(Tdisp(1, 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("body 'b': inertia violates the triangle inequality"));
  }
  SECTION("not symmetric") {
    Model m = pendulum();
    m.body("b")
        .mass(1.0)
        .inertia(Mat3{Expr(0.2), Expr(0.01), Expr(0), Expr(0), Expr(0.2), Expr(0), Expr(0), Expr(0),
                      Expr(0.2)})
        .motion(Tdisp(1, 0, 0));
    CHECK_THROWS_WITH(m.validate(), Contains("body 'b': inertia is not symmetric"));
  }
  SECTION("full tensor, positive definite but off-axis, is accepted") {
    Model m = pendulum();
    m.body("b")
        .mass(1.0)
        .inertia(Mat3{Expr(0.2), Expr(0.05), Expr(0), Expr(0.05), Expr(0.2), Expr(0), Expr(0),
                      Expr(0), Expr(0.3)})
        .motion(Tdisp(1, 0, 0));
    CHECK_NOTHROW(m.validate());
  }
}

TEST_CASE("names, axes and variants are checked", "[validation]") {
  Model m = pendulum();
  CHECK_THROWS_WITH(m.body("2nd"),
                    Contains("body name '2nd' is not a C++ identifier (starts with a digit)"));
  CHECK_THROWS_WITH(Trot({Expr(1), Expr(1), Expr(0)}, Expr(0)), Contains("is not a unit vector"));
  CHECK_THROWS_WITH(m.initial(Expr(3), 1.0),
                    Contains("'3' is not a coordinate of model 'pendulum'"));
  Definition d{"toy", {"a", "b"}, [](Model&, std::string_view) {}};
  CHECK_THROWS_WITH(d.make("c"), Contains("model 'toy' has no variant 'c' (variants: a, b)"));
  CHECK_THROWS_WITH(find_definition("nope"), Contains("no model named 'nope'"));
  Model empty("empty");
  CHECK_THROWS_WITH(empty.validate(), Contains("model 'empty' has no coordinate"));
  Model nomotion("nomotion");
  nomotion.coordinate("q0");
  nomotion.body("b").mass(1.0).inertia(0.1, 0.1, 0.1);
  CHECK_THROWS_WITH(nomotion.validate(), Contains("body 'b' has no motion"));
}
