#pragma once
// The equations of motion as expressions (the paper's case 4, beyond CAGeM):
//
//   M(q, t)·qdd + h(q, qd, t) = Q
//
//   M_jk = Σ_i S_ijᵀ·I_i·S_ik,   h_j = Σ_i S_ijᵀ·f_i
//
// with S_ij body i's partial twist for qd_j (its partial angular velocity
// dw_ij and the partial velocity of the body point at O), I_i its spatial
// inertia and f_i the wrench of its momentum rate at qdd = 0, less gravity,
// all about a reference point O: the centre of mass of the root of i's tree
// of relative motions (so that the moments stay small wherever the system
// wanders). About a common point a body's partial twist is its reference's
// plus its own local part,
//
//   S_ij = S_Bj + l_ij,   l_ij = (R_B·dw_rel,j, R_B·dv_rel,j - (R_B·dw_rel,j)×c_i),
//
// (c_i: O to i's centre of mass), so the sums over bodies gather into
// composite inertias and wrenches of subtrees, as in the composite-rigid-body
// algorithm: with I^C_a and f^C_a the sums over a's subtree and F_ak = I^C_a·l_ak,
//
//   M_jk = Σ_a Σ_(c ∈ a and its references) F_ak·l_cj  (+ the transpose for c ≠ a),
//   h_j  = Σ_a l_aj·f^C_a.
//
// Where q_j moves every body that q_k moves alike (q_j above them in the
// tree), M_jk = S_j·Φ_k with Φ_k = Σ_a F_ak the momentum q_k's rate gives the
// system: one dot product however many bodies q_k drives through dependent
// parameters.
//
// A body's momentum is computed once per direction of its local twists:
// one per coordinate, or, when fewer, one per rate its local velocity holds
// (l_j = Σ_r (dr/dqd_j)·∂l/∂r, a dependent rate's dr/dqd_j being dp/dq_j) or
// one per screw of its local motion, a varying angle or displacement
// component σ_s (l_j = Σ_s (dσ_s/dq_j)·screw_s): a motion driven by dependent
// parameters has fewer of these than coordinates.
//
// A body's cost then grows with its depth, not with the square of its number
// of coordinates. Every composite quantity is a named intermediate
// (intermediates.hpp). Only the upper triangle of the symmetric M is derived.
// Needs symbolic partial velocities.

#include <vector>

#include "model/kinematics.hpp"

namespace symdyn::model {

struct Dynamics {
  std::vector<Expr> mass_matrix;  // (nq x nq) row-major; the lower triangle mirrors the upper
  std::vector<Expr> bias;         // (nq) h
  // The symbols the expressions above use besides the kinematics': the values
  // at qdd = 0 of the dependent accelerations and intermediates that differ
  // there ("<name>__0"), and the composite quantities; each after those it uses.
  std::vector<symbolic::Definition> definitions;
};

Dynamics derive_dynamics(const Model& model, const Kinematics& kinematics);

}  // namespace symdyn::model
