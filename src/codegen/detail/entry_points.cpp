#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/symbolic/print.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::codegen::detail {
namespace {

using model::Expr;
using model::Motion;

// Where outputs come from (defined below the table).
template <class Field>
Source absolute(Field Motion::*field);
template <class Field>
Source relative(Field Motion::*field);
Source absolute_partials(std::vector<model::Vec3> Motion::*field);
Source relative_partials(std::vector<model::Vec3> Motion::*field);
Source dynamics(std::vector<Expr> model::Dynamics::*field);
Source derivatives(std::vector<Expr> DynamicsDerivatives::*field);
std::vector<Expr> masses(const Quantities& q);
std::vector<Expr> inertias(const Quantities& q);
std::vector<Expr> joints(const Quantities& q);
std::vector<Expr> anchors(const Quantities& q);
std::vector<Expr> dependent_values(const Quantities& q);
std::vector<Expr> dependent_rates(const Quantities& q);
std::vector<Expr> dependent_accelerations(const Quantities& q);
Source constraints(std::vector<Expr> model::Constraints::*field);
Source constraint_derivatives(std::vector<Expr> ConstraintDerivatives::*field);
std::string numeric_partials_body(const Sizes& sizes);
std::string forward_dynamics_body(const Sizes& sizes);

// An output written sparsely (OutputSpec::sparse): its structural zeros are the caller's.
OutputSpec sparse(std::string_view name, std::string_view shape, Source source) {
  return {.name = name, .shape = shape, .source = std::move(source), .sparse = true};
}

// The catalogue. Each row is emitted in this order, declared in the header
// with its doc and its outputs' shapes, and selectable by name (--only).
//
// Adding an entry point is adding a row where it is to be emitted, and its
// declaration in docs/emitted_interface.md (tests/codegen/entry_points_test.cpp
// checks that the two agree). A row gives
//   - inputs, in the order of kInputs;
//   - outputs, each a name, a shape in nq, nbody, ndep, and a Source of its
//     expressions: a field of model::Kinematics or model::Dynamics through the
//     helpers above, or any function of Quantities; sparse(...) for one
//     written sparsely (OutputSpec::sparse), whose every caller in the runtime
//     then keeps a buffer zeroed once for it;
//   - needs: what must be derived first (the equations of motion are derived
//     only when a selected entry point needs them) or chosen;
//   - for a hand-written body instead of a program: body, note and calls.
// inverse_dynamics_derivatives below is such a row: its outputs come from
// DynamicsDerivatives through derivatives(...), derived where .needs asks.
//
// An output of the same name and values as another entry point's is one array
// of the shared program (positions' R is velocities' R); one of the same name
// and other values is renamed there (relative_accelerations_R).
std::vector<EntryPointSpec> make_catalogue() {
  using enum Input;
  // Each body's absolute motion, in the global frame.
  const OutputSpec R{"R", "nbody x 3 x 3", absolute(&Motion::R)},
      x{"x", "nbody x 3", absolute(&Motion::x)}, v{"v", "nbody x 3", absolute(&Motion::v)},
      w{"w", "nbody x 3", absolute(&Motion::w)}, a{"a", "nbody x 3", absolute(&Motion::a)},
      dw{"dw", "nbody x 3", absolute(&Motion::dw)};
  // Each body's motion relative to its reference, in the reference's axes.
  const OutputSpec rel_R{"R", "nbody x 3 x 3", relative(&Motion::R)},
      rel_x{"x", "nbody x 3", relative(&Motion::x)}, rel_v{"v", "nbody x 3", relative(&Motion::v)},
      rel_w{"w", "nbody x 3", relative(&Motion::w)}, rel_a{"a", "nbody x 3", relative(&Motion::a)},
      rel_dw{"dw", "nbody x 3", relative(&Motion::dw)};
  // Partial velocities dv_i/dqd_j and dw_i/dqd_j, symbolic; named dv_dqd and
  // dw_dqd beside the accelerations (whose dw is the angular acceleration).
  const Source pv = absolute_partials(&Motion::dv_dqd), pw = absolute_partials(&Motion::dw_dqd);
  const Source rel_pv = relative_partials(&Motion::dv_dqd),
               rel_pw = relative_partials(&Motion::dw_dqd);
  const OutputSpec partial_dv = sparse("dv", "nbody x nq x 3", pv),
                   partial_dw = sparse("dw", "nbody x nq x 3", pw);
  const OutputSpec M{"M", "nq x nq", dynamics(&model::Dynamics::mass_matrix)},
      h{"h", "nq", dynamics(&model::Dynamics::bias)};
  const Needs absolute_motion{.absolute_motion = true};
  const Needs symbolic{.absolute_motion = true, .partials = Partials::symbolic};
  const Needs relative_symbolic{.partials = Partials::symbolic};
  const Needs equations{.absolute_motion = true, .equations_of_motion = true};
  const Needs equations_symbolic{
      .absolute_motion = true, .partials = Partials::symbolic, .equations_of_motion = true};
  const Needs recursive{
      .absolute_motion = true, .equations_of_motion = true, .recursive_dynamics = true};
  // The derivatives of tau = M·qdd + h.
  const OutputSpec dtau_dq{"dtau_dq", "nq x nq", derivatives(&DynamicsDerivatives::dtau_dq)},
      dtau_dqd{"dtau_dqd", "nq x nq", derivatives(&DynamicsDerivatives::dtau_dqd)};
  const Needs tau_derivatives{
      .absolute_motion = true, .equations_of_motion = true, .derivatives = Derivatives::dynamics};
  return {
      {.name = "inertia",
       .doc = "Mass of every body and its inertia tensor at G in body axes.",
       .inputs = {param},
       .outputs = {{"mass", "nbody", masses}, {"inertia", "nbody x 3 x 3", inertias}}},
      {.name = "joint_points",
       .doc = "Where each body hangs, to draw it: joint, its joint point (the origin of the frame "
              "after the\n"
              "last step of its motion that moves) from G in its axes; anchor, where that joint "
              "starts (the\n"
              "origin of the frame before the first step that moves) from its reference's G in "
              "the\n"
              "reference's axes (global for -1). Without a step that moves, both are the start "
              "of its motion.",
       .inputs = {param},
       .outputs = {{"joint", "nbody x 3", joints}, {"anchor", "nbody x 3", anchors}},
       .cold = true},
      {.name = "positions",
       .doc = "Positions only (to draw a scene).",
       .inputs = {t, q, param},
       .outputs = {R, x},
       .needs = absolute_motion},
      {.name = "velocities",
       .doc = "Positions and velocities.",
       .inputs = {t, q, qd, param},
       .outputs = {R, x, v, w},
       .needs = absolute_motion},
      {.name = "accelerations",
       .doc = "Positions, velocities and accelerations.",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {R, x, v, w, a, dw},
       .needs = absolute_motion},
      {.name = "relative_accelerations",
       .doc = "Each body's motion relative to its reference (reference_body; the ground for -1), "
              "in the\n"
              "reference's axes, as CAGeM emitted it: compose as EasyDyn did "
              "(runtime/relative_motion.hpp).",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {rel_R, rel_x, rel_v, rel_w, rel_a, rel_dw}},
      {.name = "partial_velocities",
       .doc = "Partial velocities dv/dqd and dw/dqd (symbolic).",
       .inputs = {t, q, param},
       .outputs = {partial_dv, partial_dw},
       .needs = symbolic},
      {.name = "partial_velocities",
       .doc = "Partial velocities dv/dqd and dw/dqd, numeric as in EasyDyn: velocities are affine "
              "in qd, so\n"
              "dv/dqd_j = v(qd = e_j) - v(qd = 0) exactly.",
       .inputs = {t, q, param},
       .outputs = {{"dv", "nbody x nq x 3", {}}, {"dw", "nbody x nq x 3", {}}},
       .needs = {.absolute_motion = true, .partials = Partials::numeric},
       .body = numeric_partials_body,
       .note = "(loops over velocities)",
       .calls = "velocities"},
      {.name = "relative_partial_velocities",
       .doc = "Partial velocities of each body's motion relative to its reference, in the "
              "reference's axes.",
       .inputs = {t, q, param},
       .outputs = {sparse("dv", "nbody x nq x 3", rel_pv), sparse("dw", "nbody x nq x 3", rel_pw)},
       .needs = relative_symbolic},
      // Accelerations and partial velocities in one call: the sines, cosines
      // and rotations both need are computed once.
      {.name = "accelerations_partials",
       .doc = "accelerations and partial_velocities in one call (dv_dqd, dw_dqd: their dv, dw).",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {R, x, v, w, a, dw, sparse("dv_dqd", "nbody x nq x 3", pv),
                   sparse("dw_dqd", "nbody x nq x 3", pw)},
       .needs = symbolic},
      {.name = "relative_accelerations_partials",
       .doc = "relative_accelerations and relative_partial_velocities in one call (dv_dqd, dw_dqd: "
              "their dv, dw).",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {rel_R, rel_x, rel_v, rel_w, rel_a, rel_dw,
                   sparse("dv_dqd", "nbody x nq x 3", rel_pv),
                   sparse("dw_dqd", "nbody x nq x 3", rel_pw)},
       .needs = relative_symbolic},
      {.name = "dependent_parameters",
       .doc = "Dependent parameters and their first and second time derivatives.",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {{"p", "ndep", dependent_values},
                   {"pd", "ndep", dependent_rates},
                   {"pdd", "ndep", dependent_accelerations}}},
      // Closed loops (model/constraints.hpp): q here is x = (q, p), the nind
      // independent coordinates then the ncon implicit dependent parameters.
      {.name = "constraints",
       .doc = "The loops' equations g(t, x) = 0 and their Jacobians g_q = dg/dq, g_p = dg/dp, "
              "g_t = dg/dt\n"
              "at x = q (independent coordinates, then implicit dependent parameters).",
       .inputs = {t, q, param},
       .outputs = {{"g", "ncon", constraints(&model::Constraints::g)},
                   {"g_q", "ncon x nind", constraints(&model::Constraints::g_q)},
                   {"g_p", "ncon x ncon", constraints(&model::Constraints::g_p)},
                   {"g_t", "ncon", constraints(&model::Constraints::g_t)}},
       .needs = {.loops = true}},
      {.name = "constraint_bias",
       .doc = "gamma such that g_q qdd + g_p pdd + gamma = 0 (d/dt(g_x) xd + d/dt(g_t)), at x = "
              "q, xd = qd.",
       .inputs = {t, q, qd, param},
       .outputs = {{"gamma", "ncon", constraints(&model::Constraints::gamma)}},
       .needs = {.loops = true}},
      // The exact Jacobians of the dynamics reduced to the independent
      // coordinates (runtime/loop_closure.hpp): with the tree's derivatives.
      {.name = "constraint_derivatives",
       .doc = "With a = g_x xdd + gamma (the loops' equations differentiated twice in time): "
              "a_x = da/dx,\n"
              "a_xd = da/dxd (ncon x nq each), and the Hessian of mu . g, hessian = d2(mu . "
              "g)/dx2 (nq x nq),\n"
              "at x = q, xd = qd, xdd = qdd; row-major.",
       .inputs = {t, q, qd, qdd, param, mu},
       .outputs = {{"a_x", "ncon x nq", constraint_derivatives(&ConstraintDerivatives::a_x)},
                   {"a_xd", "ncon x nq", constraint_derivatives(&ConstraintDerivatives::a_xd)},
                   {"hessian", "nq x nq", constraint_derivatives(&ConstraintDerivatives::hessian)}},
       .needs = {.absolute_motion = true,
                 .equations_of_motion = true,
                 .derivatives = Derivatives::dynamics,
                 .loops = true}},
      {.name = "closure_points",
       .doc = "The point of each equation's loop closure (close_loop: body a's point) in global "
              "axes, at x = q;\n"
              "0 for a loop given by its equations. Where the closure's force acts (the "
              "runtime's loop reactions).",
       .inputs = {t, q, param},
       .outputs = {{"point", "ncon x 3", constraints(&model::Constraints::point)}},
       .needs = {.loops = true},
       .cold = true},
      {.name = "mass_matrix",
       .doc = "Mass matrix M(q, t).",
       .inputs = {t, q, param},
       .outputs = {M},
       .needs = equations},
      {.name = "bias_forces",
       .doc = "h(q, qd, t): inertia terms at qdd = 0 and gravity (M qdd + h = Q).",
       .inputs = {t, q, qd, param},
       .outputs = {h},
       .needs = equations},
      // The runtime's hot path: M and h in one call, so that the sines,
      // cosines and rotations they share are computed once, with (for force
      // elements) the kinematics and partial velocities of the same state.
      {.name = "dynamics",
       .doc = "M and h together (the runtime's hot path without force elements).",
       .inputs = {t, q, qd, param},
       .outputs = {M, h},
       .needs = equations},
      {.name = "dynamics_positions",
       .doc = "M and h with the positions and partial velocities that force elements read.",
       .inputs = {t, q, qd, param},
       .outputs = {M, h, R, x, partial_dv, partial_dw},
       .needs = equations_symbolic},
      {.name = "dynamics_velocities",
       .doc = "M and h with the positions, velocities and partial velocities that force elements "
              "read.",
       .inputs = {t, q, qd, param},
       .outputs = {M, h, R, x, v, w, partial_dv, partial_dw},
       .needs = equations_symbolic},
      {.name = "inverse_dynamics",
       .doc = "tau = M qdd + h by recursive Newton-Euler (linear in the bodies).",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {{"tau", "nq", dynamics(&model::Dynamics::inverse)}},
       .needs = equations},
      {.name = "inverse_dynamics_derivatives",
       .doc = "dtau/dq and dtau/dqd of tau = M qdd + h at (q, qd, qdd), exact, the dependent "
              "parameters'\n"
              "chain rule included; row-major: dtau_dq[i * nq + j] = dtau_i/dq_j.",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {dtau_dq, dtau_dqd},
       .needs = tau_derivatives},
      // The three Jacobians of the residual in one pass: the recursive
      // derivatives' M = S_k·P_i shares S and P with dtau_dq and dtau_dqd.
      {.name = "inverse_dynamics_jacobians",
       .doc = "inverse_dynamics_derivatives' dtau_dq and dtau_dqd with dtau/dqdd = M (nq x nq, "
              "symmetric) in\n"
              "one call, sharing their terms (the recursive derivatives' M_ki = S_k . P_i).",
       .inputs = {t, q, qd, qdd, param},
       .outputs = {dtau_dq,
                   dtau_dqd,
                   {"M", "nq x nq", derivatives(&DynamicsDerivatives::mass_matrix)}},
       .needs = tau_derivatives},
      {.name = "kinematics_derivatives",
       .doc =
           "The derivatives with respect to q of every body's velocities and partial velocities "
           "(for the\n"
           "exact derivatives of force elements): dv_dq[(i * nq + k) * 3 + c] = dv_ic/dq_k, and\n"
           "ddv_dq[((i * nq + j) * nq + k) * 3 + c] = d(dv_i/dqd_j)_c/dq_k; dw_dq, ddw_dq "
           "likewise.",
       .inputs = {t, q, qd, param},
       .outputs = {sparse("dv_dq", "nbody x nq x 3", derivatives(&DynamicsDerivatives::dv_dq)),
                   sparse("dw_dq", "nbody x nq x 3", derivatives(&DynamicsDerivatives::dw_dq)),
                   sparse("ddv_dq", "nbody x nq x nq x 3",
                          derivatives(&DynamicsDerivatives::ddv_dq)),
                   sparse("ddw_dq", "nbody x nq x nq x 3",
                          derivatives(&DynamicsDerivatives::ddw_dq))},
       .needs = {.absolute_motion = true,
                 .partials = Partials::symbolic,
                 .equations_of_motion = true,
                 .derivatives = Derivatives::all}},
      {.name = "forward_dynamics_pivots",
       .doc = "qdd = M^-1 (tau - h) by the articulated-body algorithm, with each coordinate's "
              "pivot d of\n"
              "the LDL^T factorization of its body's D = S^T I^A S and the diagonal entry of D it "
              "came from.",
       .inputs = {t, q, qd, tau, param},
       .outputs = {{"qdd_solved", "nq", dynamics(&model::Dynamics::forward)},
                   {"pivots", "nq x 2", dynamics(&model::Dynamics::pivots)}},
       .needs = recursive},
      {.name = "forward_dynamics",
       .doc = "qdd = M^-1 (tau - h) without M; returns -1, or the first coordinate whose pivot is "
              "not\n"
              "positive or is below 64 ulps of its diagonal entry (then qdd is not to be used).",
       .inputs = {t, q, qd, tau, param},
       .outputs = {{"qdd", "nq", {}}},
       .needs = recursive,
       .returns = "int",
       .body = forward_dynamics_body,
       .note = "(forward_dynamics_pivots and the pivot check)",
       .calls = "forward_dynamics_pivots"},
      {.name = "joint_reactions",
       .doc = "The wrench each body's joint (its motion relative to reference_body, or the "
              "ground)\n"
              "transmits onto it from its reference, with gravity, the inertia forces and the "
              "applied\n"
              "loads F_applied, M_applied (at each G, global axes): reaction[6 i .. 6 i + 2] the "
              "force,\n"
              "[6 i + 3 .. 6 i + 5] the moment about its joint point, both in the body's axes.",
       .inputs = {t, q, qd, qdd, param, F_applied, M_applied},
       .outputs = {{"reaction", "nbody x 6", dynamics(&model::Dynamics::reactions)}},
       .needs = {.absolute_motion = true, .equations_of_motion = true, .reactions = true},
       .cold = true},
  };
}

// One field of every body's absolute (or, with `relative`, relative) motion, flattened.
template <class Field>
Source motion_field(Field Motion::*field, bool relative) {
  return [field, relative](const Quantities& q) {
    std::vector<Expr> out;
    for (const model::BodyKinematics& b : q.kinematics.bodies) {
      const Field& value = relative ? b.relative.*field : b.*field;
      out.insert(out.end(), value.begin(), value.end());
    }
    return out;
  };
}

template <class Field>
Source absolute(Field Motion::*field) {
  return motion_field(field, false);
}

template <class Field>
Source relative(Field Motion::*field) {
  return motion_field(field, true);
}

// dv/dqd or dw/dqd of every body: (nbody x nq x 3).
Source partials(std::vector<model::Vec3> Motion::*field, bool relative) {
  return [field, relative](const Quantities& q) {
    std::vector<Expr> out;
    for (const model::BodyKinematics& b : q.kinematics.bodies) {
      for (const model::Vec3& v : relative ? b.relative.*field : b.*field)
        out.insert(out.end(), v.begin(), v.end());
    }
    return out;
  };
}

Source absolute_partials(std::vector<model::Vec3> Motion::*field) {
  return partials(field, false);
}
Source relative_partials(std::vector<model::Vec3> Motion::*field) {
  return partials(field, true);
}

Source dynamics(std::vector<Expr> model::Dynamics::*field) {
  return [field](const Quantities& q) {
    if (q.dynamics == nullptr)
      throw std::logic_error("generate: an output of the dynamics without them derived");
    return q.dynamics->*field;
  };
}

Source constraints(std::vector<Expr> model::Constraints::*field) {
  return [field](const Quantities& q) {
    if (q.constraints == nullptr)
      throw std::logic_error("generate: an output of the loops' equations without loops");
    return q.constraints->*field;
  };
}

Source constraint_derivatives(std::vector<Expr> ConstraintDerivatives::*field) {
  return [field](const Quantities& q) {
    if (q.constraint_derivatives == nullptr) {
      throw std::logic_error("generate: an output of the loops' derivatives without them derived");
    }
    return q.constraint_derivatives->*field;
  };
}

Source derivatives(std::vector<Expr> DynamicsDerivatives::*field) {
  return [field](const Quantities& q) {
    if (q.derivatives == nullptr)
      throw std::logic_error("generate: an output of the derivatives without them derived");
    return q.derivatives->*field;
  };
}

std::vector<Expr> masses(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::Body& b : q.model.bodies()) out.push_back(b.mass());
  return out;
}

std::vector<Expr> inertias(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::Body& b : q.model.bodies())
    out.insert(out.end(), b.inertia().begin(), b.inertia().end());
  return out;
}

// Whether a step moves (a joint's): it depends on a symbol other than a
// run-time parameter, as for the joint point of joint_reactions.
bool moves(const model::Transform::Step& s) {
  const std::vector<Expr> values =
      s.is_rotation ? std::vector<Expr>{s.angle}
                    : std::vector<Expr>(s.displacement.begin(), s.displacement.end());
  const std::vector<Expr> symbols = symbolic::free_symbols(values);
  return std::any_of(symbols.begin(), symbols.end(),
                     [](Expr x) { return x.symbol_kind() != symbolic::SymbolKind::Parameter; });
}

// A body's motion as steps [0, first) · [first, last) · [last, n): the
// constant steps before its joint, the joint, the constant steps after it.
// Both 0 without a step that moves: the joint is then the start of the motion.
struct JointSteps {
  std::size_t first = 0, last = 0;
};

JointSteps joint_steps(const std::vector<model::Transform::Step>& steps) {
  JointSteps j;
  for (std::size_t k = steps.size(); k-- > 0;) {
    if (!moves(steps[k])) continue;
    if (j.last == 0) j.last = k + 1;
    j.first = k;
  }
  return j;
}

// The frame after steps [begin, end) in the frame before them: its axes R and origin x.
std::pair<model::Mat3, model::Vec3> frame_after(const std::vector<model::Transform::Step>& steps,
                                                std::size_t begin, std::size_t end) {
  using model::operator*;
  using model::operator+;
  model::Mat3 R = model::identity3();
  model::Vec3 x = model::zero3();
  for (std::size_t k = begin; k < end; ++k) {
    if (steps[k].is_rotation) {
      R = R * model::Transform::rotation_matrix(steps[k].axis, steps[k].angle);
    } else {
      x = x + R * steps[k].displacement;
    }
  }
  return {R, x};
}

// J from G in G's axes: G's frame is J's moved by the steps after the joint,
// G = J + R·x, so J = -Rᵀ·x.
std::vector<Expr> joints(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::Body& b : q.model.bodies()) {
    const auto& steps = b.motion().steps();
    const auto [R, x] = frame_after(steps, joint_steps(steps).last, steps.size());
    for (const Expr c : model::transpose_times(R, x)) out.push_back(-c);
  }
  return out;
}

std::vector<Expr> anchors(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::Body& b : q.model.bodies()) {
    const auto& steps = b.motion().steps();
    const model::Vec3 x = frame_after(steps, 0, joint_steps(steps).first).second;
    out.insert(out.end(), x.begin(), x.end());
  }
  return out;
}

std::vector<Expr> dependent_values(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::DependentKinematics& d : q.kinematics.dependents)
    out.push_back(d.symbols.symbol);
  return out;
}

std::vector<Expr> dependent_rates(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::DependentKinematics& d : q.kinematics.dependents) out.push_back(d.symbols.rate);
  return out;
}

std::vector<Expr> dependent_accelerations(const Quantities& q) {
  std::vector<Expr> out;
  for (const model::DependentKinematics& d : q.kinematics.dependents)
    out.push_back(d.symbols.acceleration);
  return out;
}

// Numeric partial velocities, as EasyDyn: velocities are affine in qd, so
// dv/dqd_j = v(qd = e_j) - v(qd = 0) exactly.
std::string numeric_partials_body(const Sizes& sizes) {
  return fmt::format(
      "  double R[{0} * 9], x[{0} * 3], v0[{0} * 3], w0[{0} * 3], v[{0} * 3], w[{0} * 3];\n"
      "  double qd[{1}] = {{}};\n"
      "  velocities(t, q, qd, param, R, x, v0, w0);\n"
      "  for (int j = 0; j < {1}; ++j) {{\n"
      "    qd[j] = 1.0;\n"
      "    velocities(t, q, qd, param, R, x, v, w);\n"
      "    qd[j] = 0.0;\n"
      "    for (int i = 0; i < {0}; ++i) {{\n"
      "      for (int k = 0; k < 3; ++k) {{\n"
      "        dv[(i * {1} + j) * 3 + k] = v[i * 3 + k] - v0[i * 3 + k];\n"
      "        dw[(i * {1} + j) * 3 + k] = w[i * 3 + k] - w0[i * 3 + k];\n"
      "      }}\n"
      "    }}\n"
      "  }}\n",
      sizes.nbody, sizes.nq);
}

// Below this share of its diagonal entry of D a pivot of the articulated-body
// algorithm is rounding: the runtime's SpdSolver::kSingularRatio (64 ulps).
constexpr double kSingularPivotRatio = 64 * 2.220446049250313e-16;

// forward_dynamics: the emitted pivots checked as the runtime's SpdSolver
// checks M's, so that a failing call can fall back to M and its diagnostics.
std::string forward_dynamics_body(const Sizes& sizes) {
  return fmt::format(
      "  double pivots[{0}];\n"
      "  forward_dynamics_pivots(t, q, qd, tau, param, qdd, pivots);\n"
      "  for (int j = 0; j < {1}; ++j) {{\n"
      "    const double d = pivots[2 * j], diagonal = pivots[2 * j + 1];\n"
      "    if (!(d > 0.0 && d > {2} * diagonal)) return j;\n"
      "  }}\n"
      "  return -1;\n",
      2 * sizes.nq, sizes.nq, symbolic::cpp_literal(kSingularPivotRatio));
}

// The value of one dimension of a shape.
std::size_t dimension(std::string_view d, const Sizes& sizes) {
  if (d == "nq") return sizes.nq;
  if (d == "nbody") return sizes.nbody;
  if (d == "ndep") return sizes.ndep;
  if (d == "nind") return sizes.nind;
  if (d == "ncon") return sizes.ncon;
  std::size_t n = 0;
  const auto [end, error] = std::from_chars(d.data(), d.data() + d.size(), n);
  if (error != std::errc() || end != d.data() + d.size()) {
    throw std::logic_error(
        fmt::format("generate: '{}' is not a dimension of an entry point's output", d));
  }
  return n;
}

// The dimensions of a shape, in order.
std::vector<std::size_t> dimensions(std::string_view shape, const Sizes& sizes) {
  constexpr std::string_view kTimes = " x ";
  std::vector<std::size_t> out;
  for (std::size_t sep = shape.find(kTimes);; sep = shape.find(kTimes)) {
    out.push_back(dimension(shape.substr(0, sep), sizes));
    if (sep == std::string_view::npos) return out;
    shape.remove_prefix(sep + kTimes.size());
  }
}

}  // namespace

std::string_view input_name(Input input) {
  constexpr std::string_view kNames[] = {"t",     "q",         "qd",        "qdd", "tau",
                                         "param", "F_applied", "M_applied", "mu"};
  return kNames[static_cast<std::size_t>(input)];
}

std::string shape_text(std::string_view shape, const Sizes& sizes) {
  return fmt::format("({})", fmt::join(dimensions(shape, sizes), " x "));
}

std::size_t shape_size(std::string_view shape, const Sizes& sizes) {
  std::size_t n = 1;
  for (std::size_t d : dimensions(shape, sizes)) n *= d;
  return n;
}

std::span<const EntryPointSpec> catalogue() {
  static const std::vector<EntryPointSpec> rows = make_catalogue();
  return rows;
}

std::vector<std::string_view> entry_point_names() {
  std::vector<std::string_view> names;
  for (const EntryPointSpec& e : catalogue()) {
    if (std::find(names.begin(), names.end(), e.name) == names.end()) names.push_back(e.name);
  }
  return names;
}

bool is_entry_point(std::string_view name) {
  return std::any_of(catalogue().begin(), catalogue().end(),
                     [&](const EntryPointSpec& e) { return e.name == name; });
}

EntryPoint build_entry_point(const EntryPointSpec& spec, const Quantities& quantities,
                             const Sizes& sizes) {
  EntryPoint e{.spec = &spec, .outputs = {}, .body = spec.body ? spec.body(sizes) : std::string()};
  for (const OutputSpec& o : spec.outputs) {
    std::vector<Expr> values = o.source ? o.source(quantities) : std::vector<Expr>();
    e.outputs.push_back(
        {std::string(o.name), shape_text(o.shape, sizes), std::move(values), o.sparse});
  }
  return e;
}

}  // namespace symdyn::codegen::detail
