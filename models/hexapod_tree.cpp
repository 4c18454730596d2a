// Six-legged robot with serial legs (docs/models.md 7), for comparison with
// libraries that handle kinematic trees only: 19 bodies, 24 DOF.
#include <fmt/format.h>

#include "hexapod_base.hpp"

namespace {

using namespace symdyn::model;
using symdyn::models::hips;

void build(Model& m, std::string_view) {
  const Expr height = symdyn::models::floating_main_body(m);
  for (int k = 0; k < 6; ++k) {
    const auto& hip = hips[k];
    const Expr yaw = m.coordinate(fmt::format("hip_yaw_{}", k)),
               pitch = m.coordinate(fmt::format("hip_pitch_{}", k)),
               knee = m.coordinate(fmt::format("knee_{}", k));
    const std::string coxa = fmt::format("coxa_{}", k), femur = fmt::format("femur_{}", k);
    m.body(coxa)
        .mass(1.0)
        .inertia(0.002, 0.002, 0.002)
        .relative_to("body")
        .motion(Tdisp(hip.x, hip.y, 0) * Trotz(hip.psi() + yaw) * Tdisp(0.05, 0, 0));
    m.body(femur)
        .mass(2.0)
        .inertia(0.002, 0.015, 0.015)
        .relative_to(coxa)
        .motion(Tdisp(0.05, 0, 0) * Troty(pitch) * Tdisp(0.15, 0, 0));
    m.body(fmt::format("tibia_{}", k))
        .mass(2.0)
        .inertia(0.002, 0.03, 0.03)
        .relative_to(femur)
        .motion(Tdisp(0.15, 0, 0) * Troty(knee) * Tdisp(0.2, 0, 0));
    m.initial(pitch, 0.3);
    m.initial(knee, 1.2);
  }
  m.gravity(0, 0, -9.81);
  m.initial(height, 0.5);
}

const Registration registration({"hexapod_tree", {"default"}, build});

}  // namespace
