// Six-legged walking robot in the spirit of AMRU5 (paper Table 7; docs/models.md 5):
// 49 bodies, 24 DOF, 12 dependent parameters. Each leg is a closed loop
// (two sliders, a thigh and a shank meeting at the knee) whose two angles
// alpha_k, beta_k are explicit functions of the sliders' positions.
#include <fmt/format.h>

#include "hexapod_base.hpp"

namespace {

using namespace symdyn::model;
using symdyn::models::hips;

// Bar lengths: thigh a, shank b, and the pantograph (link6 hinged on the
// thigh at am from P, link7, foot lever lf).
constexpr double a = 0.3, b = 0.25, am = 0.1, bn = 0.25, lf = 0.35;

void build(Model& m, std::string_view variant) {
  m.inline_dependents(variant == "inline");
  const Expr height = symdyn::models::floating_main_body(m);
  for (int k = 0; k < 6; ++k) {
    const auto& hip = hips[k];
    // The hip's yaw and the vertical and horizontal sliders' positions.
    const Expr yaw = m.coordinate(fmt::format("hip_yaw_{}", k)),
               v = m.coordinate(fmt::format("vertical_{}", k)),
               h = m.coordinate(fmt::format("horizontal_{}", k));
    // In the leg plane (x outwards, z up): P = (0.1, v) on the vertical slider,
    // Q = (h, -0.1) on the horizontal one, D = Q - P; the thigh from P at angle
    // alpha and the shank from Q at angle beta meet at the knee (law of cosines).
    const Expr Dx = h - 0.1, Dz = -0.1 - v;
    const Expr r = sqrt(Dx * Dx + Dz * Dz);
    const Expr alpha = m.dependent(fmt::format("alpha_{}", k),
                                   atan2(-Dz, Dx) + acos((a * a + r * r - b * b) / (2 * a * r)));
    const Expr beta =
        m.dependent(fmt::format("beta_{}", k), atan2(Dz + a * sin(alpha), a * cos(alpha) - Dx));
    auto name = [k](std::string_view part) { return fmt::format("{}_{}", part, k); };
    m.body(name("coxa"))
        .mass(1.0)
        .inertia(0.002, 0.002, 0.002)
        .relative_to("body")
        .motion(Tdisp(hip.x, hip.y, 0) * Trotz(hip.psi() + yaw) * Tdisp(0.05, 0, 0));
    m.body(name("vertical_slider"))
        .mass(0.5)
        .inertia(0.001, 0.001, 0.001)
        .relative_to(name("coxa"))
        .motion(Tdisp(0.05, 0, v));
    m.body(name("horizontal_slider"))
        .mass(0.5)
        .inertia(0.001, 0.001, 0.001)
        .relative_to(name("coxa"))
        .motion(Tdisp(h - 0.05, 0, -0.1));
    m.body(name("thigh"))
        .mass(1.0)
        .inertia(0.001, 0.0075, 0.0075)
        .relative_to(name("vertical_slider"))
        .motion(Troty(alpha) * Tdisp(a / 2, 0, 0));
    m.body(name("shank"))
        .mass(0.8)
        .inertia(0.001, 0.0041666666666666667, 0.0041666666666666667)
        .relative_to(name("horizontal_slider"))
        .motion(Troty(beta) * Tdisp(b / 2, 0, 0));
    m.body(name("link6"))
        .mass(0.4)
        .inertia(0.0005, 0.0020833333333333333, 0.0020833333333333333)
        .relative_to(name("thigh"))
        .motion(Tdisp(am - a / 2, 0, 0) * Troty(beta - alpha) * Tdisp(bn / 2, 0, 0));
    m.body(name("link7"))
        .mass(0.6)
        .inertia(0.0005, 0.006125, 0.006125)
        .relative_to(name("link6"))
        .motion(Tdisp(bn / 2, 0, 0) * Troty(alpha - beta) * Tdisp(lf / 2, 0, 0));
    m.body(name("foot"))
        .mass(0.2)
        .inertia(1e-4, 1e-4, 1e-4)
        .relative_to(name("link7"))
        .motion(Tdisp(lf / 2, 0, 0) * Troty(-alpha));
    m.initial(h, 0.35);
  }
  m.gravity(0, 0, -9.81);
  m.initial(height, 0.62);
}

const Registration registration({"amru5", {"inline", "dependent"}, build});

}  // namespace
