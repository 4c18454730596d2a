#pragma once
// The equations of motion as expressions (the paper's case 4, beyond CAGeM):
//
//   M(q, t)·qdd + h(q, qd, t) = Q
//
//   M_jk = Σ_i S_ijᵀ·I_i·S_ik,   h_j = Σ_i S_ijᵀ·f_i
//
// with S_ij body i's partial twist for qd_j, I_i its spatial inertia and f_i
// the wrench of its momentum rate at qdd = 0, less gravity. Every body's
// quantities are taken in its own axes about its centre of mass G, as in
// Featherstone's recursive algorithms: there its inertia is the constant one
// given, and the twists its own motion adds are short (a hinge's axis, a
// slider's direction): a leg that moves in a plane stays sparse however its
// hip turns. A body's twist and its acceleration at qdd = 0 come from its
// reference's (gravity enters as the ground's acceleration -g):
//
//   ω = Rᵀ·ω_B + ω_l,   v = Rᵀ·v_B + (Rᵀ·ω_B)×r + v_l,   ...
//
// (R, r: the body's orientation and position relative to its reference B,
// r in the body's axes; ω_l, v_l its local twist, summed over the screws of
// its motion: the unit twist of each varying angle or displacement component
// σ, times dσ/dt). Wrenches and inertias gather up the tree of references,
// child to parent, as in the composite-rigid-body algorithm:
//
//   f^C_B = f_B + Σ_children X·f^C_c,   I^C_B = I_B + Σ_children X·I^C_c·Xᵀ.
//
// A body's local twist for qd_j is Σ_d c_dj·l_d over a few directions l_d of
// its own: one per coordinate, or, when fewer, one per rate its motion holds
// (a dependent rate's coefficient being dp/dq_j) or one per screw (with
// coefficients dσ/dq_j): a motion driven by dependent parameters has fewer of
// these than coordinates. With F_d = I^C_a·l_d the momentum of a's subtree
// moving along l_d, and G_k(a) the momentum q_k's rate gives a's subtree
// (Σ_d c_dk·F_d plus the children's G_k carried up: G'_k(a), their part),
//
//   h_j  = Σ_a Σ_d c_dj·l_d·f^C_a,
//   M_jk = Σ_a Σ_d c_dj·l_d·G_k(a) + Σ_a Σ_d c_dk·l_d·G'_j(a),
//
// the pairs of bodies where q_j drives the upper one, then q_k. Every gathered
// quantity is a named intermediate (intermediates.hpp). Only the upper
// triangle of the symmetric M is derived.
//
// Inverse dynamics, tau = M·qdd + h, in time linear in the bodies (recursive
// Newton-Euler): qdd adds to each body's acceleration at qdd = 0
//
//   α = X·α_B + Σ_d β_d·l_d,   β_d = Σ_j c_dj·qdd_j,
//
// whose momentum rate I·α gathers up like f, so tau_j = h_j + Σ_a Σ_d c_dj·l_d·(I·α)^C_a.
//
// Forward dynamics, qdd = M⁻¹·(tau - h) without M, by the articulated-body
// algorithm, where every coordinate drives the local motion of one body only
// (a tree whose dependent parameters, if any, couple no two bodies): with S
// the body's local twists of its own k coordinates (6 x k), children first,
//
//   I^A = I + Σ_c X·I^a_c·Xᵀ,  p^A = f + Σ_c X·p^a_c,  U = I^A·S,  D = Sᵀ·U = L·diag(d)·Lᵀ,
//   Y = U·L⁻ᵀ,  z = L⁻¹·(tau - Sᵀ·p^A),
//   I^a = I^A - Σ_m Y_m·Y_mᵀ/d_m,   p^a = p^A + Σ_m Y_m·z_m/d_m,
//
// then parents first, α' = X·α_B, qdd = L⁻ᵀ·diag(d)⁻¹·(z - Yᵀ·α'), α = α' + S·qdd.
// These are taken in each body's joint frame F, after the last varying step
// of its motion (a hinge's S is its axis there), and carried between frames
// step by step of the motions, a child's constant steps merged with its
// reference's: an elementary rotation and one displacement per body.
//
// Joint reactions, where asked: the wrench each body's joint (its motion
// relative to its reference) transmits onto it from its reference, from the
// same backward pass. With A_i the applied wrench at G_i (inputs, global axes,
// turned to the body's), gathered children first like f and I·α,
//
//   W_i = f^C_i + (I·α)^C_i - A^C_i,
//
// in the body's axes about G_i (gravity is in f: the ground accelerates at
// -g), then moved to the joint point J_i, the origin of the frame after the
// last varying step of its motion (a hinge's centre): n_J = n_G + (G - J)×f.

#include <string>
#include <vector>

#include <symdyn/model/kinematics.hpp>

namespace symdyn::model {

struct Dynamics {
  std::vector<Expr> mass_matrix;  // (nq x nq) row-major; the lower triangle mirrors the upper
  std::vector<Expr> bias;         // (nq) h
  std::vector<Expr> inverse;      // (nq) tau = M·qdd + h, in the symbols qdd
  // Where the articulated-body algorithm applies (else empty, and `why_not`
  // says why): qdd = M⁻¹·(tau - h) in the symbols generalized_force_symbols(),
  // and for every coordinate the pivot d of the LDLᵀ factorization of its
  // body's D and the diagonal entry of D it came from.
  std::vector<Expr> forward;  // (nq)
  std::vector<Expr> pivots;   // (nq x 2)
  std::string why_not;
  // Only where derive_dynamics was asked for them: every body's joint reaction
  // (nbody x 6), force then moment about its joint point, in its axes, in the
  // symbols qdd and applied_load_symbols().
  std::vector<Expr> reactions;
  // The symbols the expressions above use besides the kinematics': the values
  // at qdd = 0 of the dependent accelerations ("<name>__0"), and the gathered
  // quantities; each after those it uses.
  std::vector<symbolic::Definition> definitions;
};

// The symbols of the generalized forces tau (nq), "tau.<coordinate>", inputs
// of the forward dynamics.
std::vector<Expr> generalized_force_symbols(const Model& model);

// The symbols of the loads applied at every body's G in global axes, inputs
// of the joint reactions: forces "F_applied.<body>.x" (nbody x 3), then
// moments "M_applied.<body>.x" (nbody x 3).
std::vector<Expr> applied_force_symbols(const Model& model);
std::vector<Expr> applied_moment_symbols(const Model& model);

// Uses the kinematics' relative motions and dependent parameters; `simplify`
// (if any) simplifies the rates of the motions' angles and displacements.
// `reactions`: also the joint reactions (they need the absolute orientations).
Dynamics derive_dynamics(const Model& model, const Kinematics& kinematics,
                         const SimplifyFunction& simplify = {}, bool reactions = false);

}  // namespace symdyn::model
