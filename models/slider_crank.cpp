// Slider-crank (paper Tables 4-5, eqs. 1-5; docs/models.md 3). Variants:
// inline and dependent, alpha and x given in closed form; implicit, alpha and
// x determined by the loop closed at the crank pin (docs/builder.md), the
// same mechanics.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view variant) {
  m.inline_dependents(variant == "inline");
  const Expr crank = m.coordinate("crank");  // the crank's angle
  const double l1 = 0.1, l2 = 0.3;
  const bool implicit = variant == "implicit";
  // Implicit, alpha and x have names of their own: a symbol's name has one kind
  // in a process that builds several variants (and models: the trike's x).
  const Expr alpha = implicit ? m.implicit_dependent("rod_angle", 0.0)
                              : m.dependent("alpha", asin(l1 * sin(crank) / l2));
  const Expr x = implicit ? m.implicit_dependent("slider_x", l1 + l2)
                          : m.dependent("slider_position", l1 * cos(crank) + l2 * cos(alpha));
  m.body("crank")
      .mass(1.0)
      .inertia(1e-4, 8.3333333333333333e-4, 8.3333333333333333e-4)
      .motion(Trotz(crank) * Tdisp(l1 / 2, 0, 0));
  m.body("rod")
      .mass(0.5)
      .inertia(1e-4, 3.75e-3, 3.75e-3)
      .motion(Tdisp(x, 0, 0) * Trotz(-alpha) * Tdisp(-l2 / 2, 0, 0));
  m.body("slider").mass(0.3).inertia(1e-4, 1e-4, 1e-4).motion(Tdisp(x, 0, 0));
  m.gravity(0, -9.81, 0);
  m.initial(crank, 0.0, 50.0);
  // The crank's pin (its end, l1/2 from G) is the rod's end (l2/2 behind G).
  if (implicit) m.close_loop("crank_pin", "crank", {l1 / 2, 0, 0}, "rod", {-l2 / 2, 0, 0});
}

const Registration registration({"slider_crank", {"inline", "dependent", "implicit"}, build});

}  // namespace
