#pragma once
// The derivatives of the inverse dynamics tau(q, qd, qdd) = M·qdd + h with
// respect to q and qd (Options::derivatives), exact: forward mode through the
// derivation's definitions (symbolic::chain_jacobian), so that the dependent
// parameters' chain rule, the intermediates and the gathered quantities are
// differentiated once each and shared. Of the two forms of tau, the
// recursive Newton-Euler one (linear in the bodies: its derivatives grow as
// nq²) and M·qdd + h (short for a few coordinates), the one whose derivatives
// have fewer operations is kept, as the dynamics choose between M and the
// articulated-body algorithm; and a third, the recursive derivative algorithm
// (model/dynamics_derivatives.hpp: a few spatial products per pair of joints,
// not nq times the inverse dynamics), where the model's joints allow it.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/dynamics_derivatives.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/symbolic/expr.hpp>

namespace symdyn::codegen::detail {

struct DynamicsDerivatives {
  std::vector<model::Expr> dtau_dq, dtau_dqd;  // (nq x nq) row-major: [i·nq + j] = dtau_i/dx_j
  // dtau/dqdd = M (nq x nq, symmetric): the recursive derivatives' own where
  // theirs is the form kept (sharing their terms), else the dynamics' M.
  std::vector<model::Expr> mass_matrix;
  // The derivatives of the kinematics force elements read, with respect to q
  // (with symbolic partial velocities; else empty): of each body's velocity
  // and angular velocity, [i][k][c] = ∂v_ic/∂q_k (nbody x nq x 3), and of its
  // partial velocities, [i][j][k][c] = ∂(dv_ij)_c/∂q_k (nbody x nq x nq x 3).
  std::vector<model::Expr> dv_dq, dw_dq, ddv_dq, ddw_dq;
  bool kinematics = false;  // they were derived
  std::vector<symbolic::Definition>
      definitions;     // the derivatives of the defined symbols they read
  std::string reason;  // which form, and why: for --stats and the header
};

// Both forms are differentiated only when the longer one has at most this many
// times the other's operations (chain_64's M·qdd + h has 50 000, its
// recursive form 9 000, and their derivatives 2.6 million against 0.6 million).
inline constexpr std::size_t kDerivativeFormRatio = 2;

// The operations of a program computing `outputs` from (t, q, qd, qdd,
// param) through the definitions.
using OperationCounter = std::function<std::size_t(const std::vector<model::Expr>& outputs,
                                                   const std::vector<symbolic::Definition>&)>;

// `q`, `qd`, `qdd`: the coordinates' symbols; `definitions`: those tau and the
// kinematics read, each after those it uses. `recursive`: the third form, by
// the recursive derivative algorithm (model/dynamics_derivatives.hpp), kept
// where it has the fewest operations, or why it does not apply.
// `kinematics`: also theirs, or null.
DynamicsDerivatives derive_dynamics_derivatives(
    const model::Dynamics& dynamics, model::InverseDynamicsDerivatives recursive,
    const model::Kinematics* kinematics, const std::vector<model::Expr>& q,
    const std::vector<model::Expr>& qd, const std::vector<model::Expr>& qdd,
    const std::vector<symbolic::Definition>& definitions, const OperationCounter& operations);

}  // namespace symdyn::codegen::detail
