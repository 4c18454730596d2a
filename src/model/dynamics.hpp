#pragma once
// The equations of motion as expressions (the paper's case 4, beyond CAGeM):
//
//   M(q, t)·qdd + h(q, qd, t) = Q
//
//   M_jk = Σ_i m_i·dv_ij·dv_ik + (R_iᵀ·dw_ij)·I_i·(R_iᵀ·dw_ik)
//   h_j  = Σ_i m_i·(a_i⁰ - g)·dv_ij + (I_i·Ω̇_i⁰ + Ω_i×(I_i·Ω_i))·(R_iᵀ·dw_ij)
//
// with dv_ij = dv_i/dqd_j, dw_ij = dw_i/dqd_j, Ω = Rᵀ·w and Ω̇ = Rᵀ·dw the
// angular velocity and acceleration in body axes (so J = R·I·Rᵀ is never
// formed), and ⁰ the accelerations at qdd = 0. Only the upper triangle of the
// symmetric M is derived. Needs symbolic partial velocities.

#include <vector>

#include "model/kinematics.hpp"

namespace symdyn::model {

struct Dynamics {
  std::vector<Expr> mass_matrix;  // (nq x nq) row-major; the lower triangle mirrors the upper
  std::vector<Expr> bias;         // (nq) h
  // The accelerations at qdd = 0 use the dependent parameters' accelerations at
  // qdd = 0, pdd⁰_k, and the intermediates' values at qdd = 0 where they
  // differ: defined here (symbols and their expressions, in order).
  std::vector<symbolic::Definition> zero_qdd_definitions;
};

Dynamics derive_dynamics(const Model& model, const Kinematics& kinematics);

}  // namespace symdyn::model
