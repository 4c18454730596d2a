// A heavy symmetric top whose tip stays at the origin, in ZXZ Euler angles:
// precession psi (q0) about the vertical z, nutation theta (q1), spin phi (q2)
// about the top's axis, along which its centre of mass lies.
#include "spinning_top_parameters.hpp"
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;
using namespace spinning_top;

void build(Model& m, std::string_view /*variant*/) {
  const auto q = m.coordinates(3);
  m.body("top")
      .mass(kMass)
      .inertia(kTransverseInertia, kTransverseInertia, kAxialInertia)
      .motion(Trotz(q[0]) * Trotx(q[1]) * Trotz(q[2]) * Tdisp(0, 0, kTipToCentre));
  m.gravity(0, 0, -kGravity);

  // Steady precession: psi' = W, theta' = 0, and phi' such that w3 = phi' + psi' cos(theta).
  const double precession = steady_precession_rate();
  m.initial(q[0], 0.0, precession);
  m.initial(q[1], kNutation, 0.0);
  m.initial(q[2], 0.0, kSpin - precession * std::cos(kNutation));
}

const Registration registration({"spinning_top", {"default"}, build});

}  // namespace
