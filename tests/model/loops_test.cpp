// Closed loops in the builder API (model.hpp, docs/builder.md): implicit
// dependent parameters, constraint and close_loop, and their validation errors
// naming the loop; the loops' derived Jacobians and bias against differences
// of their equations (model/constraints.hpp).
#include <catch2/catch.hpp>
#include <cmath>

#include <symdyn/model/constraints.hpp>
#include <symdyn/model/model.hpp>
#include <symdyn/symbolic/eval.hpp>

using namespace symdyn::model;
using Catch::Matchers::Contains;

namespace {

// A planar four-bar (crank lb0, coupler lb1 relative to it, rocker lb2), its loop
// closed at C by close_loop when `close`; symbols prefixed "lb_" (names have one kind).
struct FourBar {
  Model m{"loop_builder"};
  Expr q0, phi, psi;
};

void four_bar(FourBar& f, bool close = true) {
  Model& m = f.m;
  f.q0 = m.coordinate("lb_q0");
  f.phi = m.implicit_dependent("lb_phi", 0.9);
  f.psi = m.implicit_dependent("lb_psi", 1.9);
  m.body("crank").mass(0.2).inertia(1e-6, 1e-4, 1e-4).motion(Trotz(f.q0) * Tdisp(0.05, 0, 0));
  m.body("coupler")
      .mass(0.5)
      .inertia(1e-6, 5e-3, 5e-3)
      .relative_to("crank")
      .motion(Tdisp(0.05, 0, 0) * Trotz(f.phi) * Tdisp(0.175, 0, 0));
  m.body("rocker")
      .mass(0.4)
      .inertia(1e-6, 3e-3, 3e-3)
      .motion(Tdisp(0.4, 0, 0) * Trotz(f.psi) * Tdisp(0.15, 0, 0));
  if (close) m.close_loop("C", "coupler", {0.175, 0, 0}, "rocker", {0.15, 0, 0});
}

}  // namespace

TEST_CASE("close_loop keeps the equations that are not identically zero", "[loops]") {
  FourBar f;
  four_bar(f);
  REQUIRE(f.m.loops().size() == 1);
  CHECK(f.m.loops()[0].name == "C");
  CHECK(f.m.loops()[0].equations.size() == 2);  // x and y; z is 0 in the plane
  // The implicit parameters are coordinates after the independent one.
  REQUIRE(f.m.coordinates().size() == 3);
  CHECK(f.m.num_independent() == 1);
  CHECK(f.m.num_implicit() == 2);
  CHECK(f.m.coordinates()[1].q == f.phi);
  CHECK(f.m.coordinates()[1].implicit);
  CHECK(f.m.coordinates()[1].initial == 0.9);
  // A coordinate declared after them still comes before them.
  const Expr q1 = f.m.coordinate("lb_q1");
  CHECK(f.m.coordinates()[1].q == q1);
  CHECK(f.m.num_independent() == 2);
}

TEST_CASE("the gap of close_loop is the difference of the two points' positions", "[loops]") {
  FourBar f;
  four_bar(f);
  // At q0 = 0.3, phi = 0.8, psi = 1.7: C of the coupler less C of the rocker.
  const double q0 = 0.3, phi = 0.8, psi = 1.7;
  symdyn::symbolic::Bindings<double> values{{f.q0, q0}, {f.phi, phi}, {f.psi, psi}};
  symdyn::symbolic::Evaluator<double> evaluate(values);
  const double cx = 0.1 * std::cos(q0) + 0.35 * std::cos(q0 + phi),
               cy = 0.1 * std::sin(q0) + 0.35 * std::sin(q0 + phi);
  const double dx = 0.4 + 0.3 * std::cos(psi), dy = 0.3 * std::sin(psi);
  CHECK(evaluate(f.m.loops()[0].equations[0]) == Approx(cx - dx).margin(1e-15));
  CHECK(evaluate(f.m.loops()[0].equations[1]) == Approx(cy - dy).margin(1e-15));
}

TEST_CASE("loop validation names the loop", "[loops][validation]") {
  SECTION("more equations than implicit parameters") {
    FourBar f;
    four_bar(f, false);
    f.m.constraint("C3", {f.phi - f.psi, f.phi + f.psi - 1, sin(f.phi) - f.q0});
    CHECK_THROWS_WITH(f.m.validate(),
                      Contains("loop 'C3' (3 equations) gives 3 equations for 2 implicit "
                               "dependent parameters (lb_phi, lb_psi)"));
  }
  SECTION("fewer equations than implicit parameters") {
    FourBar f;
    four_bar(f, false);
    f.m.constraint("half", {f.phi - f.psi - f.q0});
    CHECK_THROWS_WITH(f.m.validate(), Contains("loop 'half' (1 equation) gives 1 equation for 2"));
  }
  SECTION("an implicit parameter in no loop") {
    FourBar f;
    four_bar(f, false);
    f.m.constraint("only_phi", {f.phi - f.q0, cos(f.phi) - 0.5 * f.q0});
    CHECK_THROWS_WITH(f.m.validate(),
                      Contains("implicit dependent parameter 'lb_psi' appears in no loop"));
  }
  SECTION("a loop on the coordinates alone") {
    FourBar f;
    four_bar(f);
    f.m.constraint("rigid", {f.q0 - 1});
    CHECK_THROWS_WITH(f.m.validate(),
                      Contains("loop 'rigid' depends on no implicit dependent parameter"));
  }
  SECTION("implicit parameters without loops") {
    FourBar f;
    four_bar(f, false);
    CHECK_THROWS_WITH(f.m.validate(), Contains("'lb_phi' appears in no loop"));
  }
  SECTION("builder errors") {
    FourBar f;
    four_bar(f);
    CHECK_THROWS_WITH(f.m.close_loop("C", "crank", {0, 0, 0}, "rocker", {0, 0, 0}),
                      Contains("loop 'C' is declared twice"));
    CHECK_THROWS_WITH(f.m.close_loop("D", "crank", {0, 0, 0}, "slider", {0, 0, 0}),
                      Contains("loop 'D' closes on 'slider', which is not a body"));
    f.m.body("late").mass(1.0).inertia(1, 1, 1);
    CHECK_THROWS_WITH(f.m.close_loop("E", "late", {0, 0, 0}, "rocker", {0, 0, 0}),
                      Contains("loop 'E' closes on body 'late', which has no motion yet"));
    CHECK_THROWS_WITH(f.m.constraint("F", {Expr(0), Expr(2)}),
                      Contains("loop 'F' equation 1 is the constant 2, never 0"));
    CHECK_THROWS_WITH(f.m.constraint("G", {f.q0 - f.q0}),
                      Contains("loop 'G' has no equation that is not identically 0"));
    CHECK_THROWS_WITH(f.m.constraint("bad name", {f.phi}), Contains("loop name 'bad name'"));
    CHECK_THROWS_WITH(f.m.implicit_dependent("lb_phi", 0.0),
                      Contains("implicit dependent parameter 'lb_phi' is declared twice"));
    CHECK_THROWS_WITH(f.m.implicit_dependent("lb_nan", std::nan("")),
                      Contains("'lb_nan': guess nan is not finite"));
  }
}

TEST_CASE("the loops' Jacobians and bias are the derivatives of their equations", "[loops]") {
  FourBar f;
  four_bar(f);
  const Model& m = f.m;
  const Kinematics k = derive_kinematics(m);
  const Constraints c = derive_constraints(m, k);
  REQUIRE(c.g.size() == 2);
  REQUIRE(c.g_q.size() == 2);
  REQUIRE(c.g_p.size() == 4);
  const double x[] = {0.3, 0.8, 1.7}, xd[] = {2.0, -1.0, 0.5};
  const auto bind = [&](const double* at) {
    symdyn::symbolic::Bindings<double> b;
    for (int j = 0; j < 3; ++j) {
      b.emplace(m.coordinates()[static_cast<std::size_t>(j)].q, at[j]);
      b.emplace(m.coordinates()[static_cast<std::size_t>(j)].qd, xd[j]);
    }
    return b;
  };
  const auto value = [&](Expr e, const double* at) {
    const symdyn::symbolic::Bindings<double> values = bind(at);
    symdyn::symbolic::Evaluator<double> evaluate(values);
    return evaluate(e);
  };
  const double h = 1e-6;
  for (int i = 0; i < 2; ++i) {
    CAPTURE(i);
    double jacobian_rate = 0.0;
    for (int j = 0; j < 3; ++j) {
      double plus[3] = {x[0], x[1], x[2]}, minus[3] = {x[0], x[1], x[2]};
      plus[j] += h, minus[j] -= h;
      const double difference = (value(c.g[i], plus) - value(c.g[i], minus)) / (2 * h);
      const Expr entry = j == 0 ? c.g_q[i] : c.g_p[i * 2 + (j - 1)];
      CHECK(value(entry, x) == Approx(difference).margin(1e-8));
      // d/dt of the entry along xd, for gamma.
      double along_plus[3], along_minus[3];
      for (int l = 0; l < 3; ++l)
        along_plus[l] = x[l] + h * xd[l], along_minus[l] = x[l] - h * xd[l];
      jacobian_rate += (value(entry, along_plus) - value(entry, along_minus)) / (2 * h) * xd[j];
    }
    CHECK(value(c.g_t[i], x) == 0.0);
    CHECK(value(c.gamma[i], x) == Approx(jacobian_rate).margin(1e-7));
  }
}
