// Slider-crank (paper Tables 4-5, eqs. 1-5; docs/models.md 3).
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view variant) {
  m.inline_dependents(variant == "inline");
  const Expr q0 = m.coordinate("q0");
  const double l1 = 0.1, l2 = 0.3;
  const Expr alpha = m.dependent("alpha", asin(l1 * sin(q0) / l2));
  const Expr x = m.dependent("x", l1 * cos(q0) + l2 * cos(alpha));
  m.body("crank")
      .mass(1.0)
      .inertia(1e-4, 8.3333333333333333e-4, 8.3333333333333333e-4)
      .motion(Trotz(q0) * Tdisp(l1 / 2, 0, 0));
  m.body("rod")
      .mass(0.5)
      .inertia(1e-4, 3.75e-3, 3.75e-3)
      .motion(Tdisp(x, 0, 0) * Trotz(-alpha) * Tdisp(-l2 / 2, 0, 0));
  m.body("slider").mass(0.3).inertia(1e-4, 1e-4, 1e-4).motion(Tdisp(x, 0, 0));
  m.gravity(0, -9.81, 0);
  m.initial(q0, 0.0, 50.0);
}

const Registration registration({"slider_crank", {"inline", "dependent"}, build});

}  // namespace
