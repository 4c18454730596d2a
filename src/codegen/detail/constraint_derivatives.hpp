#pragma once
// The derivatives of the closed loops' equations that the exact Jacobians of
// the reduced dynamics need (runtime/loop_closure.hpp), in x = (q, p), the
// tree's extended coordinates:
//
//   a       = g_x·xdd + gamma          (g differentiated twice in time, ncon)
//   a_x     = ∂a/∂x,  a_xd = ∂a/∂xd    (ncon x nq; a_xd = 2·∂(g_x·xd + g_t)/∂x)
//   hessian = ∂²(mu·g)/∂x²             (nq x nq)
//
// contracted with the run-time vectors xdd and mu rather than emitted as
// ncon·nq² second derivatives: forward mode through the derivation's
// definitions (symbolic::chain_jacobian), as the dynamics' derivatives.

#include <vector>

#include <symdyn/model/constraints.hpp>
#include <symdyn/symbolic/expr.hpp>

namespace symdyn::codegen::detail {

struct ConstraintDerivatives {
  std::vector<model::Expr> a_x, a_xd;  // (ncon x nq) row-major
  std::vector<model::Expr> hessian;    // (nq x nq) row-major
  std::vector<symbolic::Definition>
      definitions;  // the derivatives of the defined symbols they read
};

// `q`, `qd`, `qdd`: the extended coordinates' symbols; `mu`: one per equation;
// `definitions`: those the constraints read, each after those it uses.
ConstraintDerivatives derive_constraint_derivatives(
    const model::Constraints& constraints, const std::vector<model::Expr>& q,
    const std::vector<model::Expr>& qd, const std::vector<model::Expr>& qdd,
    const std::vector<model::Expr>& mu, const std::vector<symbolic::Definition>& definitions);

}  // namespace symdyn::codegen::detail
