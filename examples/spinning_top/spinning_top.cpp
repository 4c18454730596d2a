// A heavy symmetric top whose tip stays at the origin, in ZXZ Euler angles:
// precession psi about the vertical z, nutation theta, spin phi about the
// top's axis, along which its centre of mass lies.
#include "spinning_top_parameters.hpp"
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;
using namespace spinning_top;

void build(Model& m, std::string_view /*variant*/) {
  const Expr psi = m.coordinate("psi");
  const Expr theta = m.coordinate("theta");
  const Expr phi = m.coordinate("phi");
  m.body("top")
      .mass(kMass)
      .inertia(kTransverseInertia, kTransverseInertia, kAxialInertia)
      .motion(Trotz(psi) * Trotx(theta) * Trotz(phi) * Tdisp(0, 0, kTipToCentre));
  m.gravity(0, 0, -kGravity);

  // Steady precession: psi' = W, theta' = 0, and phi' such that w3 = phi' + psi' cos(theta).
  const double precession = steady_precession_rate();
  m.initial(psi, 0.0, precession);
  m.initial(theta, kNutation, 0.0);
  m.initial(phi, 0.0, kSpin - precession * std::cos(kNutation));
}

const Registration registration({"spinning_top", {"default"}, build});

}  // namespace
