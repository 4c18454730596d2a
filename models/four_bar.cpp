// A crank-rocker four-bar linkage (Grashof: s + l = 0.5 < p + q = 0.65),
// planar in xy, closed at the joint C of the coupler and the rocker; no
// closed form is given: the coupler's angle phi (relative to the crank) and
// the rocker's psi are implicit dependent parameters (docs/builder.md,
// docs/models.md).
//
//   crank   O = (0, 0)   -> A, length r1, angle crank
//   coupler A            -> C, length r2, angle crank + phi
//   rocker  D = (d, 0)   -> C, length r3, angle psi
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

// Variants: closed, its lengths folded into the code; parametric, the same
// with run-time parameters r1, r2, r3, d (other geometries, one code).

// A slender rod of mass m and length l along its x axis (the inertia of the
// default lengths in both variants).
Body& rod(Body& b, double m, double l) {
  const double across = m * l * l / 12;
  return b.mass(m).inertia(1e-6, across, across);
}

void build(Model& m, std::string_view variant) {
  const bool runtime = variant == "parametric";
  const Expr r1 = m.parameter("r1", 0.1, runtime), r2 = m.parameter("r2", 0.35, runtime),
             r3 = m.parameter("r3", 0.3, runtime), d = m.parameter("d", 0.4, runtime);
  const Expr crank = m.coordinate("crank");  // the crank's angle
  // The assembly with C above the ground line at crank = 0 (guesses near it).
  const Expr phi = m.implicit_dependent("phi", 0.9);
  const Expr psi = m.implicit_dependent("psi", 1.9);
  rod(m.body("crank"), 0.2, 0.1).motion(Trotz(crank) * Tdisp(r1 / 2, 0, 0));
  rod(m.body("coupler"), 0.5, 0.35)
      .relative_to("crank")
      .motion(Tdisp(r1 / 2, 0, 0) * Trotz(phi) * Tdisp(r2 / 2, 0, 0));
  rod(m.body("rocker"), 0.4, 0.3).motion(Tdisp(d, 0, 0) * Trotz(psi) * Tdisp(r3 / 2, 0, 0));
  m.close_loop("C", "coupler", {r2 / 2, 0, 0}, "rocker", {r3 / 2, 0, 0});
  m.gravity(0, -9.81, 0);
  m.initial(crank, 0.0, 5.0);
}

const Registration registration({"four_bar", {"closed", "parametric"}, build});

}  // namespace
