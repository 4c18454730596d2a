#pragma once
// The derivatives of the inverse dynamics tau = M·qdd + h with respect to q
// and qd by the recursive algorithm of Carpentier & Mansard (2018, as
// Pinocchio's computeRNEADerivatives), written with Expr: O(nq) spatial
// products per joint, then two or four 6-vector dot products per pair of
// joints one of which is the other's ancestor.
//
// It works over joints: every coordinate q_j moves through one elementary
// step, a rotation by an angle linear in the coordinates about a constant
// axis or a translation linear in them, every other step constant; S_j is
// that step's twist per unit of qd_j (its unit twist times dσ/dq_j: the
// screws of one step commute, each coordinate in it a joint of its own),
// in world axes about the origin (spatial vectors as Featherstone's), so
// that the twist of every body after it gains S_j·qd_j and, turning it,
// dS_i/dq_j = S_j × S_i for every joint i after j. With ψ_j, α_j the twist
// and acceleration before joint j (α of the ground: -g),
//
//   v_j = ψ_j + S_j·qd_j,   a_j = α_j + S_j·qdd_j + (ψ_j × S_j)·qd_j,
//   dV_j = ψ_j × S_j,       dA_j = α_j × S_j + ψ_j × dV_j,
//
// and a body's wrench f = I·a + v ×* I·v (I its spatial inertia about the
// origin, a and v those of its last joint). Gathered over the bodies after
// joint j: the inertia I^C_j, the wrench F_j, the momentum H_j and the
// symmetric B_j = Σ (v ×* I - I·v×) (so that D·x = B·x + x ×* H is the
// derivative of f along a change x of the twist, the turning part apart):
//
//   P_j = I^C_j·S_j,   Q_j = B_j·S_j - S_j ×* H_j,
//   dF_j = S_j ×* F_j + I^C_j·dA_j + B_j·dV_j + dV_j ×* H_j,
//   dFv_j = 2·I^C_j·dV_j + B_j·S_j + S_j ×* H_j,
//
// and tau_i = S_iᵀ·F_i gives, for k = i or an ancestor of i,
//
//   dtau_i/dq_k = P_i·dA_k + Q_i·dV_k,   dtau_i/dqd_k = 2·P_i·dV_k + Q_i·S_k,
//   dtau_k/dq_i = S_k·dF_i,              dtau_k/dqd_i = S_k·dFv_i,
//
// and zero between joints on different branches; with them the mass matrix
// dtau/dqdd, M_ki = M_ik = S_k·P_i for the same pairs (as Pinocchio's
// computeRNEADerivatives gives it), sharing S and P. A coordinate may move
// several bodies (a motion given from the ground, each link's the product of
// the chain up to it) where the steps before it, its direction and the joint
// before it are the same for all of them: then it is one joint of a tree. Where these conditions
// fail (a dependent parameter, a step moving in time or not linear in the coordinates, a coordinate
// in two different places) `why_not` says why, and the other forms serve.

#include <string>
#include <vector>

#include <symdyn/model/kinematics.hpp>

namespace symdyn::model {

struct InverseDynamicsDerivatives {
  std::vector<Expr> dtau_dq, dtau_dqd;            // (nq x nq) row-major: [i·nq + j] = dtau_i/dx_j
  std::vector<Expr> mass_matrix;                  // (nq x nq) dtau/dqdd, symmetric
  std::vector<symbolic::Definition> definitions;  // the symbols they use, each after its own
  std::string why_not;  // where the algorithm does not apply (and the rest is empty)
};

// Uses the kinematics' absolute orientations and centres of mass.
InverseDynamicsDerivatives derive_inverse_dynamics_derivatives(const Model& model,
                                                               const Kinematics& kinematics);

}  // namespace symdyn::model
