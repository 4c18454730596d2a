#pragma once
// The closed loops' equations for the runtime (coordinate partitioning):
// with x = (q, p) the tree's extended coordinates (q independent, p the
// implicit dependent parameters) and g(t, x) = 0 the loops' equations
// (nc of them, nc = dim p),
//
//   g_q = ∂g/∂q (nc x nq),  g_p = ∂g/∂p (nc x nc),  g_t = ∂g/∂t (nc),
//   γ = d/dt(g_x)·xd + d/dt(g_t)  (g at zero accelerations: g̈ = g_x·ẍ + γ),
//
// total derivatives: an explicit dependent parameter used by g carries its
// own dependence on x through its Jacobian (DependentKinematics). At run
// time pd = -g_p⁻¹·(g_q·qd + g_t) and pdd = -g_p⁻¹·(g_q·qdd + γ).

#include <vector>

#include <symdyn/model/kinematics.hpp>

namespace symdyn::model {

struct Constraints {
  std::vector<Expr> g;      // (nc)
  std::vector<Expr> g_q;    // (nc x nq) row-major, nq the independent coordinates
  std::vector<Expr> g_p;    // (nc x nc)
  std::vector<Expr> g_t;    // (nc)
  std::vector<Expr> gamma;  // (nc), in x, xd, t
  // The point of each equation's loop closure in global axes (body a's point of
  // close_loop), 0 for a loop given by its equations: where its force acts.
  std::vector<Expr> point;  // (nc x 3)
};

// The equations of every loop, in order; empty for a model without loops.
Constraints derive_constraints(const Model& model, const Kinematics& kinematics,
                               const SimplifyFunction& simplify = {});

}  // namespace symdyn::model
