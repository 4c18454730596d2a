#pragma once
// Energy and momentum of the bodies of a model, from velocity-level kinematics.
//
//   kinetic       T = sum_i 1/2 m_i v_i.v_i + 1/2 w_i.(J_i w_i),  J_i = R_i I_i R_i^T
//                 (global axes: EasyDyn used I_i unrotated, wrong for bodies
//                 whose inertia axes are not aligned with the global ones)
//   gravitational V = -sum_i m_i x_i.g
//   linear        p = sum_i m_i v_i
//   angular       L = sum_i x_i x (m_i v_i) + J_i w_i    (about the global origin)

#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

struct Energies {
  double kinetic = 0.0;
  double gravitational = 0.0;
  double elastic = 0.0;  // stored in force elements
  double total() const { return kinetic + gravitational + elastic; }
};

struct Momentum {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();  // about the global origin
};

double kinetic_energy(const Model& m, const Kinematics& k);
double gravitational_energy(const Model& m, const Kinematics& k);
Momentum momentum(const Model& m, const Kinematics& k);

}  // namespace symdyn::runtime
