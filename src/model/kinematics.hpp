#pragma once
// Derivation of the kinematics of every body as expressions.
//
// For a body with an absolute motion T0G = [R x; 0 1]:
//   v = dx/dt, a = dv/dt (total time derivatives: q -> qd -> qdd, p -> pd -> pdd, t -> 1)
//   w = Σ_k R_(before k)·axis_k·d(angle_k)/dt  (exact and short; skew(w) = dR/dt·Rᵀ)
//   dw = dw/dt
// For a body relative to B, only T_BG is derived; the absolute quantities are
// composed from B's (docs/design.md), so the emitted code evaluates the composition
// numerically. B's quantities enter as named intermediates (symbols defined in
// Kinematics::intermediates), each computed once: substituted, B's sums would
// merge into the body's own and a chain's k-th body would cost O(k).
//
//   r = R_B·x_rel, x = x_B + r, R = R_B·R_rel, w = w_B + R_B·w_rel,
//   v = v_B + w_B×r + R_B·v_rel,
//   a = a_B + dw_B×r + w_B×(w_B×r) + 2·w_B×(R_B·v_rel) + R_B·a_rel,
//   dw = dw_B + w_B×(R_B·w_rel) + R_B·dw_rel.
// Partial velocities dv/dqd_j, dw/dqd_j (symbolic) differentiate the local
// velocities with respect to qd_j and are composed the same way:
//   dv_j = dv_B,j + dw_B,j×r + R_B·dv_rel,j,   dw_j = dw_B,j + R_B·dw_rel,j;
// a dependent parameter's rate pd_k carries its own dependence on qd through
// the Jacobian dp_k/dq_j (see DependentKinematics).
//
// Simplification, when asked, is progressive (as CAGeM did under Giac): the
// relative positions are simplified, velocities derived from the simplified
// positions and simplified, then accelerations.

#include <functional>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::model {

// A motion: pose, velocities, accelerations and partial velocities.
struct Motion {
  Mat3 R;
  Vec3 x, v, w, a, dw;
  std::vector<Vec3> dv_dqd, dw_dqd;  // (nq) each; empty unless symbolic partials
};

// A body's absolute motion, and its motion relative to its reference (the
// same for an absolute motion) in the reference's axes: what CAGeM emitted for
// EasyDyn to compose.
struct BodyKinematics : Motion {
  Motion relative;
};

struct DependentKinematics {
  Dependent symbols;
  Expr value, rate, acceleration;  // p, pd, pdd as expressions of q, qd, qdd, t, earlier p
  std::vector<Expr> jacobian;      // (nq) total dp/dq_j, for symbolic partial velocities
  // (nq) symbols standing for the Jacobian entries, or the entry itself when it
  // is a number or a symbol (a zero then cancels the terms it multiplies)
  std::vector<Expr> jacobian_symbols;
};

struct Kinematics {
  std::vector<BodyKinematics> bodies;           // in model order, absolute
  std::vector<DependentKinematics> dependents;  // in dependency order
  // The quantities of every body that others are relative to, as symbols of
  // kind Intermediate with their values, each after those it uses. A body's
  // expressions may use them (and dependent symbols): evaluate them in order.
  std::vector<symbolic::Definition> intermediates;
};

using SimplifyFunction = std::function<Expr(Expr)>;

struct DeriveOptions {
  SimplifyFunction simplify;  // empty: no simplification
  bool symbolic_partials = false;
  // Only what CAGeM derived: each body's motion relative to its reference
  // (BodyKinematics::relative). The absolute motion of a body relative to
  // another is not composed: it stays zero, without partials or intermediates.
  bool relative_only = false;
};

// Validates the model, then derives. Throws ModelError on an invalid model.
Kinematics derive_kinematics(const Model& model, const DeriveOptions& options = {});

}  // namespace symdyn::model
