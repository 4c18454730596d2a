// Models whose runs fail in the model's own terms, for the runtime's error tests
// (bad_input_test.cpp, integrator_errors_test.cpp): each is valid at its initial
// configuration, and leaves its domain or locks only where a test sends it.
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

// A slider-crank whose crank l1 and rod l2 are run-time parameters: with
// l1 > l2 the rod cannot follow the crank past sin(q0) = l2 / l1.
//   asin: alpha = asin(l1 sin(q0) / l2), x = l1 cos(q0) + l2 cos(alpha);
//   sqrt: s = sqrt(l2² - (l1 sin(q0))²), x = l1 cos(q0) + s, alpha = atan2(l1 sin(q0), s).
// The rod and slider are light (rod_mass, slider_mass), so that the crank reaches
// the dead point with most of its speed.
void long_crank(Model& m, std::string_view variant) {
  const Expr q0 = m.coordinate("q0");
  const Expr l1 = m.parameter("l1", 0.1, true), l2 = m.parameter("l2", 0.3, true);
  const Expr rod_mass = m.parameter("rod_mass", 0.5, true),
             slider_mass = m.parameter("slider_mass", 0.3, true);
  Expr alpha, x;
  if (variant == "asin") {
    alpha = m.dependent("alpha", asin(l1 * sin(q0) / l2));
    x = m.dependent("x", l1 * cos(q0) + l2 * cos(alpha));
  } else {
    const Expr s = m.dependent("s", sqrt(l2 * l2 - pow(l1 * sin(q0), 2)));
    alpha = m.dependent("alpha", atan2(l1 * sin(q0), s));
    x = m.dependent("x", l1 * cos(q0) + s);
  }
  m.body("crank").mass(1.0).inertia(1e-4, 8.3e-4, 8.3e-4).motion(Trotz(q0) * Tdisp(l1 / 2, 0, 0));
  m.body("rod")
      .mass(rod_mass)
      .inertia(1e-4 * rod_mass, 7.5e-3 * rod_mass, 7.5e-3 * rod_mass)
      .motion(Tdisp(x, 0, 0) * Trotz(-alpha) * Tdisp(-l2 / 2, 0, 0));
  m.body("slider")
      .mass(slider_mass)
      .inertia(3e-4 * slider_mass, 3e-4 * slider_mass, 3e-4 * slider_mass)
      .motion(Tdisp(x, 0, 0));
  m.gravity(0, 0, -9.81);
  m.initial(q0, 0.0, 10.0);
}

// A free body whose attitude is three angles: Z-Y-X (yaw, pitch, roll; Tait-Bryan,
// locked at pitch = ±90 deg) with a translation, or Z-X-Z (precession, nutation,
// spin; proper Euler, locked at nutation = 0 or 180 deg).
void gimbal(Model& m, std::string_view variant) {
  Body& frame = m.body("frame").mass(2.0).inertia(0.1, 0.2, 0.25);
  if (variant == "zyx") {
    const Expr x = m.coordinate("x"), y = m.coordinate("y"), z = m.coordinate("z");
    const Expr yaw = m.coordinate("yaw"), pitch = m.coordinate("pitch"),
               roll = m.coordinate("roll");
    frame.motion(Tdisp(x, y, z) * Trotz(yaw) * Troty(pitch) * Trotx(roll));
  } else {
    const Expr precession = m.coordinate("precession"), nutation = m.coordinate("nutation"),
               spin = m.coordinate("spin");
    frame.motion(Trotz(precession) * Trotx(nutation) * Trotz(spin));
    m.initial(nutation, 0.5);
  }
  m.gravity(0, 0, -9.81);
}

// A slider q0 (nothing acts along it: q0 = 2t from 0) turned about its own axis
// by p = c/(t - 1/2), prescribed: p has a pole at t = 1/2, where the slider's
// orientation is not defined, though the accelerations stay regular (its turning
// is not along q0: qdd = 0 on both sides).
void pole(Model& m, std::string_view) {
  const Expr q0 = m.coordinate("q0");
  const Expr c = m.parameter("c", 0.01, true);
  const Expr p = m.dependent("p", c / (m.time() - 0.5));
  m.body("slider").mass(1.0).inertia(1e-3, 1e-3, 1e-3).motion(Tdisp(q0, 0, 0) * Trotz(p));
  m.gravity(0, 0, -9.81);
  m.initial(q0, 0.0, 2.0);
}

// A slider-crank whose crank and rod are equally long (l = 0.1), its loop
// closed at the crank pin and assembled folded: the rod lies back along the
// crank (rod_angle = pi - q0, slider_x = 0), so that the slider stands still
// and crank and rod turn about fixed axes: M is constant and (gravity normal
// to the plane) q0 = 0.3 + 2t. The folded branch crosses the extended one
// (rod_angle = q0, slider_x = 2l·cos q0) at q0 = pi/2, where g_p = [[-l sin a,
// -1], [-l cos a, 0]] (a = rod_angle) is singular: det(g_p) = -l cos a. The
// pointer variant adds a pointer turned at the crank pin by beta = asin(k·cos(q0)),
// an explicit dependent parameter whose argument touches 1 at q0 = 0 where k = 1.
void branch_crank(Model& m, std::string_view variant) {
  const Expr q0 = m.coordinate("q0");
  const double l = 0.1;
  const Expr rod_angle = m.implicit_dependent("rod_angle", 3.0);
  const Expr slider_x = m.implicit_dependent("slider_x", 0.0);
  m.body("crank").mass(1.0).inertia(1e-4, 8.3e-4, 8.3e-4).motion(Trotz(q0) * Tdisp(l / 2, 0, 0));
  m.body("rod")
      .mass(0.5)
      .inertia(5e-5, 4e-4, 4e-4)
      .motion(Tdisp(slider_x, 0, 0) * Trotz(-rod_angle) * Tdisp(-l / 2, 0, 0));
  m.body("slider").mass(0.3).inertia(1e-4, 1e-4, 1e-4).motion(Tdisp(slider_x, 0, 0));
  m.gravity(0, 0, -9.81);
  m.initial(q0, 0.3, 2.0);
  m.close_loop("crank_pin", "crank", {l / 2, 0, 0}, "rod", {-l / 2, 0, 0});
  if (variant == "pointer") {
    const Expr beta = m.dependent("beta", asin(m.parameter("k", 0.5, true) * cos(q0)));
    m.body("pointer")
        .mass(0.1)
        .inertia(1e-5, 1e-5, 1e-5)
        .motion(Trotz(q0) * Tdisp(l, 0, 0) * Trotz(beta) * Tdisp(l / 4, 0, 0));
  }
}

// Two crank-rocker four-bars (models/four_bar.cpp's), one of lengths 1e-4
// times the other's, each closed at its own joint C: g_p is block diagonal,
// the small loop's rows 1e-4 times the large one's, so that g_p's pivots
// span four decades while each loop alone is far from a branch point.
void two_four_bars(Model& m, std::string_view) {
  for (const auto& [name, scale] : {std::pair{"large", 1.0}, std::pair{"small", 1e-4}}) {
    const std::string n(name);
    const Expr crank = m.coordinate(n + "_crank");
    const Expr phi = m.implicit_dependent(n + "_phi", 0.9);
    const Expr psi = m.implicit_dependent(n + "_psi", 1.9);
    const double r1 = 0.1 * scale, r2 = 0.35 * scale, r3 = 0.3 * scale, d = 0.4 * scale;
    m.body(n + "_crank")
        .mass(0.2)
        .inertia(1e-6, 1e-4, 1e-4)
        .motion(Trotz(crank) * Tdisp(r1 / 2, 0, 0));
    m.body(n + "_coupler")
        .mass(0.5)
        .inertia(1e-6, 1e-4, 1e-4)
        .relative_to(n + "_crank")
        .motion(Tdisp(r1 / 2, 0, 0) * Trotz(phi) * Tdisp(r2 / 2, 0, 0));
    m.body(n + "_rocker")
        .mass(0.4)
        .inertia(1e-6, 1e-4, 1e-4)
        .motion(Tdisp(d, 0, 0) * Trotz(psi) * Tdisp(r3 / 2, 0, 0));
    m.close_loop(n + "_C", n + "_coupler", {r2 / 2, 0, 0}, n + "_rocker", {r3 / 2, 0, 0});
    m.initial(crank, 0.0, 5.0);
  }
  m.gravity(0, -9.81, 0);
}

const Registration crank({"long_crank", {"asin", "sqrt"}, long_crank});
const Registration four_bars({"two_four_bars", {"scaled"}, two_four_bars});
const Registration branch({"branch_crank", {"folded", "pointer"}, branch_crank});
const Registration poles({"pole", {"division"}, pole});
const Registration gimbals({"gimbal", {"zyx", "zxz"}, gimbal});

}  // namespace
