#pragma once
// runtime::Model: the immutable description of one generated model, read from
// the static members of the struct the generator emits (docs/emitted_interface.md)
// by Model::from<Generated>(). The emitted code is the only bridge between
// generation and simulation: this header knows no symbolic type.
//
// Sizes: nq coordinates, nbody bodies, ndep dependent parameters, nparam
// run-time parameters. Entry points the generator did not emit are null and
// reported by has_*(); calling one that is absent throws ModelError naming it.
//
// The inertia of every body is evaluated and validated at construction and
// whenever a parameter changes (ModelError naming the body):
//   mass > 0; inertia symmetric (to 1e-9 relative); positive definite;
//   principal moments satisfying the triangle inequalities A + B >= C.

#include <array>
#include <concepts>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/kinematics_derivatives.hpp>
#include <symdyn/runtime/relative_motion.hpp>

namespace symdyn::runtime {

// Signatures of the emitted entry points (shapes in docs/emitted_interface.md).
using InertiaFn = void (*)(const double* param, double* mass, double* inertia);
using JointPointsFn = void (*)(const double* param, double* joint, double* anchor);
using PositionsFn = void (*)(double t, const double* q, const double* param, double* R, double* x);
using VelocitiesFn = void (*)(double t, const double* q, const double* qd, const double* param,
                              double* R, double* x, double* v, double* w);
using AccelerationsFn = void (*)(double t, const double* q, const double* qd, const double* qdd,
                                 const double* param, double* R, double* x, double* v, double* w,
                                 double* a, double* dw);
using PartialVelocitiesFn = void (*)(double t, const double* q, const double* param, double* dv,
                                     double* dw);
// The relative entry points have the shapes of their absolute counterparts.
using RelativeAccelerationsFn = AccelerationsFn;
using RelativePartialVelocitiesFn = PartialVelocitiesFn;
using DependentParametersFn = void (*)(double t, const double* q, const double* qd,
                                       const double* qdd, const double* param, double* p,
                                       double* pd, double* pdd);
using MassMatrixFn = void (*)(double t, const double* q, const double* param, double* M);
using BiasForcesFn = void (*)(double t, const double* q, const double* qd, const double* param,
                              double* h);
// Cold diagnostics: the arguments of the dependent parameters' restricted
// operations, (ndomain x 3): argument, exponent, scale (docs/emitted_interface.md).
using DomainArgumentsFn = void (*)(double t, const double* q, const double* param,
                                   double* arguments);
// M and h in one call, alone or with the kinematics force elements read.
using DynamicsFn = void (*)(double t, const double* q, const double* qd, const double* param,
                            double* M, double* h);
using DynamicsPositionsFn = void (*)(double t, const double* q, const double* qd,
                                     const double* param, double* M, double* h, double* R,
                                     double* x, double* dv, double* dw);
using DynamicsVelocitiesFn = void (*)(double t, const double* q, const double* qd,
                                      const double* param, double* M, double* h, double* R,
                                      double* x, double* v, double* w, double* dv, double* dw);

// tau = M·qdd + h (nq), recursive Newton-Euler.
using InverseDynamicsFn = void (*)(double t, const double* q, const double* qd, const double* qdd,
                                   const double* param, double* tau);
// dtau/dq and dtau/dqd (nq x nq each, row-major: dtau_dq[i·nq + j] = ∂tau_i/∂q_j)
// of tau = M·qdd + h at (q, qd, qdd), the dependent parameters' chain rule included.
using InverseDynamicsDerivativesFn = void (*)(double t, const double* q, const double* qd,
                                              const double* qdd, const double* param,
                                              double* dtau_dq, double* dtau_dqd);
// Those and dtau/dqdd = M (nq x nq, symmetric) in one call.
using InverseDynamicsJacobiansFn = void (*)(double t, const double* q, const double* qd,
                                            const double* qdd, const double* param, double* dtau_dq,
                                            double* dtau_dqd, double* M);
// The derivatives with respect to q of v, w (nbody x nq x 3 each) and of the
// partial velocities (nbody x nq x nq x 3 each) (runtime/kinematics_derivatives.hpp).
using KinematicsDerivativesFn = void (*)(double t, const double* q, const double* qd,
                                         const double* param, double* dv_dq, double* dw_dq,
                                         double* ddv_dq, double* ddw_dq);
// Closed loops (docs/emitted_interface.md): at x = q (extended), the loops'
// equations g (ncon), g_q (ncon x nindependent), g_p (ncon x ncon), g_t (ncon);
// and gamma (ncon) with g_q·qdd + g_p·pdd + gamma = 0.
using ConstraintsFn = void (*)(double t, const double* q, const double* param, double* g,
                               double* g_q, double* g_p, double* g_t);
using ConstraintBiasFn = void (*)(double t, const double* q, const double* qd, const double* param,
                                  double* gamma);
// With a = g_x·qdd + gamma: a_x = da/dx, a_xd = da/dxd (ncon x nq each) and the
// Hessian d²(mu·g)/dx² (nq x nq) at x = q, xd = qd, xdd = qdd, weights mu (ncon).
using ConstraintDerivativesFn = void (*)(double t, const double* q, const double* qd,
                                         const double* qdd, const double* param, const double* mu,
                                         double* a_x, double* a_xd, double* hessian);
// The point of each equation's loop closure in global axes (ncon x 3) at x = q.
using ClosurePointsFn = void (*)(double t, const double* q, const double* param, double* point);
// qdd = M⁻¹·(tau - h) (nq) by the articulated-body algorithm; returns -1, or the
// first coordinate whose pivot failed (then qdd is not to be used).
using ForwardDynamicsFn = int (*)(double t, const double* q, const double* qd, const double* tau,
                                  const double* param, double* qdd);
// The wrench each body's joint transmits onto it from its reference (nbody x
// 6: force, moment about the joint point, body axes), given the loads applied
// at every G (nbody x 3 each, global axes).
using JointReactionsFn = void (*)(double t, const double* q, const double* qd, const double* qdd,
                                  const double* param, const double* F_applied,
                                  const double* M_applied, double* reaction);

namespace detail {
template <class G>
concept has_inverse_dynamics = requires(double t, const double* c, double* o) {
  G::inverse_dynamics(t, c, c, c, c, o);
};
template <class G>
concept has_inverse_dynamics_derivatives = requires(double t, const double* c, double* o) {
  G::inverse_dynamics_derivatives(t, c, c, c, c, o, o);
};
template <class G>
concept has_inverse_dynamics_jacobians = requires(double t, const double* c, double* o) {
  G::inverse_dynamics_jacobians(t, c, c, c, c, o, o, o);
};
template <class G>
concept has_kinematics_derivatives = requires(double t, const double* c, double* o) {
  G::kinematics_derivatives(t, c, c, c, o, o, o, o);
};
template <class G>
concept has_forward_dynamics = requires(double t, const double* c, double* o) {
  { G::forward_dynamics(t, c, c, c, c, o) } -> std::convertible_to<int>;
};
template <class G>
concept has_joint_reactions = requires(double t, const double* c, double* o) {
  G::joint_reactions(t, c, c, c, c, c, c, o);
};
template <class G>
concept has_joint_points = requires(const double* c, double* o) {
  G::joint_points(c, o, o);
};
template <class G>
concept has_positions = requires(double t, const double* c, double* o) {
  G::positions(t, c, c, o, o);
};
template <class G>
concept has_velocities = requires(double t, const double* c, double* o) {
  G::velocities(t, c, c, c, o, o, o, o);
};
template <class G>
concept has_accelerations = requires(double t, const double* c, double* o) {
  G::accelerations(t, c, c, c, c, o, o, o, o, o, o);
};
template <class G>
concept has_partial_velocities = requires(double t, const double* c, double* o) {
  G::partial_velocities(t, c, c, o, o);
};
template <class G>
concept has_relative_accelerations = requires(double t, const double* c, double* o) {
  G::relative_accelerations(t, c, c, c, c, o, o, o, o, o, o);
};
template <class G>
concept has_relative_partial_velocities = requires(double t, const double* c, double* o) {
  G::relative_partial_velocities(t, c, c, o, o);
};
template <class G>
concept has_dependent_parameters = requires(double t, const double* c, double* o) {
  G::dependent_parameters(t, c, c, c, c, o, o, o);
};
template <class G>
concept has_mass_matrix = requires(double t, const double* c, double* o) {
  G::mass_matrix(t, c, c, o);
};
template <class G>
concept has_bias_forces = requires(double t, const double* c, double* o) {
  G::bias_forces(t, c, c, c, o);
};
template <class G>
concept has_dynamics = requires(double t, const double* c, double* o) {
  G::dynamics(t, c, c, c, o, o);
};
template <class G>
concept has_dynamics_positions = requires(double t, const double* c, double* o) {
  G::dynamics_positions(t, c, c, c, o, o, o, o, o, o);
};
template <class G>
concept has_dynamics_velocities = requires(double t, const double* c, double* o) {
  G::dynamics_velocities(t, c, c, c, o, o, o, o, o, o, o, o);
};
template <class G>
concept has_domain_checks = requires(double t, const double* c, double* o) {
  { G::ndomain } -> std::convertible_to<int>;
  G::dependent_names[0];
  G::domain_dependents[0];
  G::domain_functions[0];
  G::domain_arguments(t, c, c, o);
};
template <class G>
concept has_loops = requires(double t, const double* c, double* o) {
  { G::nindependent } -> std::convertible_to<int>;
  { G::nloop } -> std::convertible_to<int>;
  G::loop_names[0];
  G::constraint_loop[0];
  G::constraints(t, c, c, o, o, o, o);
  G::constraint_bias(t, c, c, c, o);
};
template <class G>
concept has_constraint_derivatives = requires(double t, const double* c, double* o) {
  G::constraint_derivatives(t, c, c, c, c, c, o, o, o);
};
template <class G>
concept has_closure_points = requires(double t, const double* c, double* o) {
  G::loop_bodies[0];
  G::constraint_axis[0];
  G::closure_points(t, c, c, o);
};
template <class G>
concept has_angle_sequences = requires {
  { G::nangle_sequences } -> std::convertible_to<int>;
  G::angle_sequence_body[0];
  G::angle_sequence_q[0];
  G::angle_sequence_axes[0];
};
template <class G>
concept generated_model = requires {
  { G::model } -> std::convertible_to<const char*>;
  { G::nq } -> std::convertible_to<int>;
  { G::nbody } -> std::convertible_to<int>;
  { G::ndep } -> std::convertible_to<int>;
  { G::nparam } -> std::convertible_to<int>;
  G::q_names[0];
  G::body_names[0];
  G::param_names[0];
  G::param_defaults[0];
  G::q_initial[0];
  G::qd_initial[0];
  G::gravity[0];
  G::reference_body[0];
  G::inertia(static_cast<const double*>(nullptr), static_cast<double*>(nullptr),
             static_cast<double*>(nullptr));
};
}  // namespace detail

// An operation of a dependent parameter with a restricted domain (asin, acos,
// sqrt, log, pow), in the order the generator emitted them.
struct DomainCheck {
  std::string dependent;  // the dependent parameter's name
  std::string function;
};

// Three elementary rotations by coordinates of one body (model/diagnostics.hpp).
struct AngleSequence {
  int body = 0;
  std::array<int, 3> coordinates{};
  std::string axes;  // "zyx": Tait-Bryan when the first and last differ, else proper Euler
};

// The static facts and entry points of a generated model, as data.
struct ModelDescription {
  std::string model, variant;
  int nq = 0, nbody = 0, ndep = 0, nparam = 0;
  std::vector<std::string> q_names, body_names, param_names;
  std::vector<double> param_defaults, q_initial, qd_initial;
  Vec3 gravity = Vec3::Zero();
  std::vector<int> reference_body;
  InertiaFn inertia = nullptr;
  JointPointsFn joint_points = nullptr;  // null for code emitted before it
  PositionsFn positions = nullptr;
  VelocitiesFn velocities = nullptr;
  AccelerationsFn accelerations = nullptr;
  PartialVelocitiesFn partial_velocities = nullptr;
  RelativeAccelerationsFn relative_accelerations = nullptr;
  RelativePartialVelocitiesFn relative_partial_velocities = nullptr;
  DependentParametersFn dependent_parameters = nullptr;
  MassMatrixFn mass_matrix = nullptr;
  BiasForcesFn bias_forces = nullptr;
  DynamicsFn dynamics = nullptr;
  DynamicsPositionsFn dynamics_positions = nullptr;
  DynamicsVelocitiesFn dynamics_velocities = nullptr;
  InverseDynamicsFn inverse_dynamics = nullptr;
  ForwardDynamicsFn forward_dynamics = nullptr;  // only where the generator chose it
  InverseDynamicsDerivativesFn inverse_dynamics_derivatives = nullptr;  // only where asked for
  InverseDynamicsJacobiansFn inverse_dynamics_jacobians = nullptr;      // likewise
  KinematicsDerivativesFn kinematics_derivatives = nullptr;             // likewise
  JointReactionsFn joint_reactions = nullptr;                           // likewise
  // Cold diagnostics; empty or null for code emitted before them.
  std::vector<std::string> dependent_names;  // (ndep)
  std::vector<DomainCheck> domain_checks;
  DomainArgumentsFn domain_arguments = nullptr;
  std::vector<AngleSequence> angle_sequences;
  // Closed loops: q holds the nindependent coordinates, then the implicit
  // dependent parameters (nq - nindependent, one per loop equation). Without
  // loops nindependent is nq (-1: set by the constructor) and the rest empty.
  int nindependent = -1;
  std::vector<std::string> loop_names;
  std::vector<int> constraint_loop;  // (nq - nindependent) the loop of each equation
  ConstraintsFn constraints = nullptr;
  ConstraintBiasFn constraint_bias = nullptr;
  ConstraintDerivativesFn constraint_derivatives = nullptr;  // only where asked for
  // close_loop's bodies a, b of each loop ((nloop x 2), -1 for a loop given by
  // its equations) and each equation's axis ((ncon), 0..2, or -1); where the
  // closures' forces act. Empty (and null) for a model emitted without them.
  std::vector<int> loop_bodies, constraint_axis;
  ClosurePointsFn closure_points = nullptr;
};

class Model {
 public:
  // Reads the static members of a generated struct. Throws ModelError if the
  // inertia of a body is not physical.
  template <detail::generated_model G>
  static Model from();
  // The description from<G>() builds the model from: header-only, so that a
  // model module (model_module.hpp) hands it over without linking the runtime.
  template <detail::generated_model G>
  static ModelDescription describe();

  // Builds from a description (what from<G>() fills); validates it.
  explicit Model(ModelDescription d);

  const std::string& name() const { return description_.model; }
  const std::string& variant() const { return description_.variant; }
  int nq() const { return description_.nq; }
  int nbody() const { return description_.nbody; }
  int ndep() const { return description_.ndep; }
  int nparam() const { return description_.nparam; }
  // Closed loops: nq = nindependent() + ncon(), the coordinates q then the
  // implicit dependent parameters p (runtime/loop_closure.hpp solves them).
  int nindependent() const { return description_.nindependent; }
  int ncon() const { return description_.nq - description_.nindependent; }
  bool has_loops() const { return ncon() > 0; }
  const std::vector<std::string>& loop_names() const { return description_.loop_names; }
  // The loop equation k belongs to.
  int constraint_loop(int k) const { return description_.constraint_loop[k]; }
  // The emitted loops' equations at x (nq): g (ncon), g_q (ncon x nindependent),
  // g_p (ncon x ncon), g_t (ncon), row-major; gamma (ncon) at x, xd.
  void constraints(double t, const double* x, double* g, double* g_q, double* g_p,
                   double* g_t) const;
  void constraint_bias(double t, const double* x, const double* xd, double* gamma) const;
  // a_x, a_xd (ncon x nq each) and the Hessian of mu·g (nq x nq), row-major, at
  // x, xd, xdd (nq each) and mu (ncon): the exact Jacobians' part of the loops.
  bool has_constraint_derivatives() const { return description_.constraint_derivatives != nullptr; }
  void constraint_derivatives(double t, const double* x, const double* xd, const double* xdd,
                              const double* mu, double* a_x, double* a_xd, double* hessian) const;
  // Loop closures (close_loop): loop l's bodies a and b, -1 for a loop given
  // by its equations (or a model emitted without closure_points); the axis
  // (0, 1, 2) of the gap equation k is a component of, or -1.
  int loop_body_a(int l) const {
    return description_.loop_bodies.empty() ? -1 : description_.loop_bodies[2 * l];
  }
  int loop_body_b(int l) const {
    return description_.loop_bodies.empty() ? -1 : description_.loop_bodies[2 * l + 1];
  }
  int constraint_axis(int k) const {
    return description_.constraint_axis.empty() ? -1 : description_.constraint_axis[k];
  }
  bool has_closure_points() const { return description_.closure_points != nullptr; }
  // The point of each equation's closure in global axes at x (ncon x 3, row-major).
  void closure_points(double t, const double* x, double* point) const;
  // The name of equation k's loop reaction: "<loop>.Fx" .. "<loop>.Fz" for a
  // closure (the force, N), "<loop>.lambda<j>" (its j-th equation) for a loop
  // given by its equations.
  std::string loop_reaction_name(int k) const;

  const std::vector<std::string>& q_names() const { return description_.q_names; }
  const std::vector<std::string>& body_names() const { return description_.body_names; }
  const std::vector<std::string>& param_names() const { return description_.param_names; }
  // Index of a body or coordinate by name; ModelError naming it if unknown.
  int body_index(std::string_view name) const;
  int coordinate_index(std::string_view name) const;
  int parameter_index(std::string_view name) const;

  // Initial coordinates and rates from the model (nq each), as a State at t = 0
  // (with loops: the implicit dependent parameters at their guesses, rates 0).
  State initial_state() const;
  const Vec3& gravity() const { return description_.gravity; }
  // Body a body's motion is relative to in the model, or -1.
  int reference_body(int i) const { return description_.reference_body[i]; }

  // Run-time parameters (nparam); setting one re-evaluates and re-validates
  // the inertia (ModelError naming the body, the model keeps its old values).
  const std::vector<double>& parameters() const { return param_; }
  void set_parameter(std::string_view name, double value);
  void set_parameters(const std::vector<double>& values);

  // Mass and inertia tensor at G in body axes of body i.
  double mass(int i) const { return mass_[i]; }
  const Mat3& inertia(int i) const { return inertia_[i]; }
  // Inertia tensor at G in global axes, J = R I R^T.
  Mat3 global_inertia(int i, const Kinematics& k) const;

  // Where each body hangs, at the current parameters (docs/emitted_interface.md,
  // joint_points): its joint point from G in its axes, and where that joint
  // starts from its reference's G in the reference's axes (global for -1).
  // Empty for code emitted without them.
  struct JointPoints {
    std::vector<Vec3> joint, anchor;  // (nbody) each
  };
  bool has_joint_points() const { return description_.joint_points != nullptr; }
  JointPoints joint_points() const;

  bool has_positions() const { return description_.positions != nullptr; }
  bool has_velocities() const { return description_.velocities != nullptr; }
  bool has_accelerations() const { return description_.accelerations != nullptr; }
  bool has_partial_velocities() const { return description_.partial_velocities != nullptr; }
  bool has_relative_accelerations() const { return description_.relative_accelerations != nullptr; }
  bool has_relative_partial_velocities() const {
    return description_.relative_partial_velocities != nullptr;
  }
  bool has_dependent_parameters() const { return description_.dependent_parameters != nullptr; }
  bool has_equations_of_motion() const {
    return description_.mass_matrix != nullptr && description_.bias_forces != nullptr;
  }
  bool has_inverse_dynamics() const { return description_.inverse_dynamics != nullptr; }
  bool has_forward_dynamics() const { return description_.forward_dynamics != nullptr; }
  bool has_inverse_dynamics_derivatives() const {
    return description_.inverse_dynamics_derivatives != nullptr;
  }
  bool has_inverse_dynamics_jacobians() const {
    return description_.inverse_dynamics_jacobians != nullptr;
  }
  bool has_kinematics_derivatives() const { return description_.kinematics_derivatives != nullptr; }
  bool has_joint_reactions() const { return description_.joint_reactions != nullptr; }

  // A kinematics buffer of the right sizes for this model.
  Kinematics make_kinematics() const {
    return Kinematics(description_.nq, description_.nbody, description_.ndep);
  }

  // Evaluate entry points into a buffer. q, qd, qdd have nq entries each.
  // positions() clears the rates; velocities() leaves a and dw untouched.
  void positions(double t, const double* q, Kinematics& k) const;
  void velocities(double t, const double* q, const double* qd, Kinematics& k) const;
  void accelerations(double t, const double* q, const double* qd, const double* qdd,
                     Kinematics& k) const;
  void partial_velocities(double t, const double* q, Kinematics& k) const;
  void dependent_parameters(double t, const double* q, const double* qd, const double* qdd,
                            Kinematics& k) const;
  // Each body's motion relative to its reference (relative_motion.hpp), into
  // a buffer from make_relative_motion(); rel.compose(k, ...) makes it absolute.
  RelativeMotion make_relative_motion() const {
    return RelativeMotion(description_.reference_body, description_.nq);
  }
  void relative_accelerations(double t, const double* q, const double* qd, const double* qdd,
                              RelativeMotion& rel) const;
  void relative_partial_velocities(double t, const double* q, RelativeMotion& rel) const;

  // Emitted equations of motion: M (nq x nq, row-major into a column-major
  // Matrix is fine since M is symmetric) and h (nq).
  void mass_matrix(double t, const double* q, double* M) const;
  void bias_forces(double t, const double* q, const double* qd, double* h) const;
  // M and h, with the kinematics up to `level` and (from positions up) the
  // partial velocities into k: one emitted call (dynamics, dynamics_positions,
  // dynamics_velocities) when the generator emitted it, else the separate
  // entry points.
  void dynamics(double t, const double* q, const double* qd, KinematicsLevel level, double* M,
                double* h, Kinematics& k) const;
  // tau = M·qdd + h (nq each), emitted recursively.
  void inverse_dynamics(double t, const double* q, const double* qd, const double* qdd,
                        double* tau) const;
  // dtau/dq and dtau/dqd (nq x nq each) at (q, qd, qdd), exact (emitted); row-major as
  // emitted, with no pass to turn them (for solves that read them row by row).
  void inverse_dynamics_derivatives(double t, const double* q, const double* qd, const double* qdd,
                                    Matrix& dtau_dq, Matrix& dtau_dqd) const;
  void inverse_dynamics_derivatives(double t, const double* q, const double* qd, const double* qdd,
                                    RowMajorMatrix& dtau_dq, RowMajorMatrix& dtau_dqd) const;
  // Those and M = dtau/dqdd (nq x nq, symmetric) in one emitted call.
  void inverse_dynamics_jacobians(double t, const double* q, const double* qd, const double* qdd,
                                  Matrix& dtau_dq, Matrix& dtau_dqd, Matrix& M) const;
  void inverse_dynamics_jacobians(double t, const double* q, const double* qd, const double* qdd,
                                  RowMajorMatrix& dtau_dq, RowMajorMatrix& dtau_dqd,
                                  Matrix& M) const;
  // The derivatives of the kinematics with respect to q at (t, q, qd), exact (emitted).
  void kinematics_derivatives(double t, const double* q, const double* qd,
                              KinematicsDerivatives& dk) const;
  KinematicsDerivatives make_kinematics_derivatives() const {
    return KinematicsDerivatives(description_.nq, description_.nbody);
  }
  // qdd = M⁻¹·(tau - h) (nq each) without M; -1, or the coordinate of the first
  // failed pivot (qdd then unusable: the mass matrix names the culprit).
  int forward_dynamics(double t, const double* q, const double* qd, const double* tau,
                       double* qdd) const;
  // Every body's joint reaction (6 x nbody, column i: force, then moment about
  // the body's joint point, in its axes; docs/runtime.md) at (q, qd, qdd) with
  // the loads F, M (3 x nbody, at each G, global axes; Loads' F and M).
  void joint_reactions(double t, const double* q, const double* qd, const double* qdd,
                       const double* F, const double* M, double* reaction) const;
  // The names of joint_reactions' rows for body i: "<body>.Fx" .. "<body>.Mz"
  // (N, then N·m).
  static constexpr std::array<const char*, 6> kReactionComponents = {"Fx", "Fy", "Fz",
                                                                     "Mx", "My", "Mz"};

  // The emitted entry points, or null: for callers that dispatch once, with parameters().data().
  InverseDynamicsFn emitted_inverse_dynamics() const { return description_.inverse_dynamics; }
  ForwardDynamicsFn emitted_forward_dynamics() const { return description_.forward_dynamics; }
  // The emitted dynamics entry point of level none (M and h only), or null: for a
  // caller that dispatches once (MultibodySystem's hot path) with parameters().data().
  DynamicsFn emitted_dynamics() const { return description_.dynamics; }

  // Cold diagnostics (error paths only; they allocate).
  // The first operation of a dependent parameter whose argument at (t, q) is
  // outside its function's domain, or at its edge where the derivative is
  // infinite: "dependent parameter 'alpha': asin(1.2) is outside its domain
  // [-1, 1]". Nothing when all are inside, or the model was emitted without checks.
  std::optional<std::string> domain_error(double t, const double* q) const;
  // Edges: near the edge of its domain, a restricted function's rate carries
  // the rounding of its argument x, about 1e-16 of x's scale (1 for asin and
  // acos, whose edges are ±1; for sqrt, log and pow the magnitude of the terms x
  // is a sum of, emitted beside x). Within kDomainMargin of the edge, relative
  // to that scale, the rate has lost half its digits: refused (the table of
  // model.cpp, docs/errors.md). A sum of squares has no edge: its scale is itself.
  static constexpr double kDomainMargin = 1e-8;
  // Per check, domain_arguments writes the argument, the exponent (pow) and the scale.
  static constexpr std::size_t kDomainValues = 3;
  // Whether any domain check has a margin (the checks below do nothing otherwise).
  bool has_domain_margins() const { return !margin_distances_.empty(); }
  // The smallest margin at (t, q) (negative outside the domain, +inf without
  // margins) and its check; arguments (kDomainValues·ndomain) is scratch. Allocates nothing.
  struct DomainMargin {
    double margin = std::numeric_limits<double>::infinity();
    int check = -1;
  };
  DomainMargin smallest_domain_margin(double t, const double* q, double* arguments) const;
  int num_domain_checks() const { return static_cast<int>(description_.domain_checks.size()); }
  // Cold: "dependent parameter 'alpha': asin(0.99999999999) is 1e-11 from the edge
  // of its function's domain [domain of asin: [-1, 1]]" for the check of that margin
  // ("sqrt(2e-10) is 1e-08 from the edge of its function's domain relative to the
  // 0.02 of the terms it is a sum of").
  std::string describe_domain_margin(double t, const double* q, const DomainMargin& m) const;
  // The first check whose edge at 0 (sqrt, log, pow) lies between two results of
  // domain_arguments (its argument changed sign), or -1: a division passed its pole.
  int domain_edge_crossed(const double* before, const double* after) const;
  // The angle sequence at its singular configuration (|cos b| or |sin b| of
  // its middle angle below 1e-4) that carries most of the null direction of M
  // (n x n, singular), if that is at least half of it: "coordinates 'yaw',
  // 'pitch', 'roll' of body 'frame' form a Z-Y-X angle sequence singular at
  // pitch = 90 deg (pitch = 1.5707963 rad)".
  std::optional<std::string> singular_angle_sequence(const double* q, const Matrix& M) const;
  // The first angle sequence whose middle angle is within `within` rad of its
  // singular value, if any: "coordinates 'yaw', 'pitch', 'roll' of body 'frame'
  // form a Z-Y-X angle sequence 1e-06 rad from its singular configuration pitch =
  // 90 deg (pitch = 1.5707953 rad)". Allocates only when it finds one.
  std::optional<std::string> angle_sequence_near_singular(const double* q, double within) const;
  const std::vector<std::string>& dependent_names() const { return description_.dependent_names; }
  const std::vector<AngleSequence>& angle_sequences() const { return description_.angle_sequences; }

 private:
  void evaluate_inertia(const std::vector<double>& param, std::vector<double>& mass,
                        std::vector<Mat3>& inertia) const;
  [[noreturn]] void missing(const char* entry) const;
  // The emitted derivatives (and M where asked: inverse_dynamics_jacobians), row-major,
  // into the storage of either matrix type.
  template <class Storage>
  void emit_inverse_dynamics_derivatives(double t, const double* q, const double* qd,
                                         const double* qdd, Storage& dtau_dq, Storage& dtau_dqd,
                                         Matrix* M) const;
  void validate_diagnostics() const;
  void validate_loops() const;
  // dynamics() from the separate entry points (a model without the fused ones).
  [[gnu::noinline]] void dynamics_separately(double t, const double* q, const double* qd,
                                             KinematicsLevel level, double* M, double* h,
                                             Kinematics& k) const;

  ModelDescription description_;
  std::vector<double> zeros_;  // (max(nq, 1)) qd = 0 for positions from velocities
  std::vector<double> param_;  // (max(nparam, 1))
  // Each domain check's distance to its edge (model.cpp's table).
  std::vector<double (*)(double x, double e, double scale)> margin_distances_;
  std::vector<bool> zero_edges_;  // each domain check's: its edge is x = 0
  std::vector<double> mass_;      // (nbody)
  std::vector<Mat3> inertia_;     // (nbody)
};

template <detail::generated_model G>
Model Model::from() {
  return Model(describe<G>());
}

template <detail::generated_model G>
ModelDescription Model::describe() {
  ModelDescription d;
  d.model = G::model;
  if constexpr (requires { G::variant; }) d.variant = G::variant;
  d.nq = G::nq;
  d.nbody = G::nbody;
  d.ndep = G::ndep;
  d.nparam = G::nparam;
  for (int j = 0; j < G::nq; ++j) {
    d.q_names.emplace_back(G::q_names[j]);
    d.q_initial.push_back(G::q_initial[j]);
    d.qd_initial.push_back(G::qd_initial[j]);
  }
  for (int i = 0; i < G::nbody; ++i) {
    d.body_names.emplace_back(G::body_names[i]);
    d.reference_body.push_back(G::reference_body[i]);
  }
  for (int k = 0; k < G::nparam; ++k) {
    d.param_names.emplace_back(G::param_names[k]);
    d.param_defaults.push_back(G::param_defaults[k]);
  }
  d.gravity = Vec3(G::gravity[0], G::gravity[1], G::gravity[2]);
  d.inertia = &G::inertia;
  if constexpr (detail::has_joint_points<G>) d.joint_points = &G::joint_points;
  if constexpr (detail::has_positions<G>) d.positions = &G::positions;
  if constexpr (detail::has_velocities<G>) d.velocities = &G::velocities;
  if constexpr (detail::has_accelerations<G>) d.accelerations = &G::accelerations;
  if constexpr (detail::has_partial_velocities<G>) d.partial_velocities = &G::partial_velocities;
  if constexpr (detail::has_relative_accelerations<G>)
    d.relative_accelerations = &G::relative_accelerations;
  if constexpr (detail::has_relative_partial_velocities<G>) {
    d.relative_partial_velocities = &G::relative_partial_velocities;
  }
  if constexpr (detail::has_dependent_parameters<G>) {
    d.dependent_parameters = &G::dependent_parameters;
  }
  if constexpr (detail::has_domain_checks<G>) {
    for (int k = 0; k < G::ndep; ++k) d.dependent_names.emplace_back(G::dependent_names[k]);
    for (int k = 0; k < G::ndomain; ++k)
      d.domain_checks.push_back({G::domain_dependents[k], G::domain_functions[k]});
    d.domain_arguments = &G::domain_arguments;
  }
  if constexpr (detail::has_loops<G>) {
    d.nindependent = G::nindependent;
    for (int l = 0; l < G::nloop; ++l) d.loop_names.emplace_back(G::loop_names[l]);
    for (int k = 0; k < G::nq - G::nindependent; ++k)
      d.constraint_loop.push_back(G::constraint_loop[k]);
    d.constraints = &G::constraints;
    d.constraint_bias = &G::constraint_bias;
    if constexpr (detail::has_constraint_derivatives<G>)
      d.constraint_derivatives = &G::constraint_derivatives;
    if constexpr (detail::has_closure_points<G>) {
      d.loop_bodies.assign(G::loop_bodies, G::loop_bodies + 2 * G::nloop);
      d.constraint_axis.assign(G::constraint_axis, G::constraint_axis + G::nq - G::nindependent);
      d.closure_points = &G::closure_points;
    }
  }
  if constexpr (detail::has_angle_sequences<G>) {
    for (int k = 0; k < G::nangle_sequences; ++k) {
      d.angle_sequences.push_back({G::angle_sequence_body[k],
                                   {G::angle_sequence_q[3 * k], G::angle_sequence_q[3 * k + 1],
                                    G::angle_sequence_q[3 * k + 2]},
                                   G::angle_sequence_axes[k]});
    }
  }
  // The flag says whether the generator emitted the equations of motion.
  bool eom = true;
  if constexpr (requires { G::has_equations_of_motion; }) eom = G::has_equations_of_motion;
  if constexpr (detail::has_mass_matrix<G> && detail::has_bias_forces<G>) {
    if (eom) {
      d.mass_matrix = &G::mass_matrix;
      d.bias_forces = &G::bias_forces;
      if constexpr (detail::has_dynamics<G>) d.dynamics = &G::dynamics;
      if constexpr (detail::has_dynamics_positions<G>)
        d.dynamics_positions = &G::dynamics_positions;
      if constexpr (detail::has_dynamics_velocities<G>)
        d.dynamics_velocities = &G::dynamics_velocities;
      if constexpr (detail::has_inverse_dynamics<G>) d.inverse_dynamics = &G::inverse_dynamics;
      if constexpr (detail::has_inverse_dynamics_derivatives<G>) {
        d.inverse_dynamics_derivatives = &G::inverse_dynamics_derivatives;
      }
      if constexpr (detail::has_inverse_dynamics_jacobians<G>)
        d.inverse_dynamics_jacobians = &G::inverse_dynamics_jacobians;
      if constexpr (detail::has_kinematics_derivatives<G>)
        d.kinematics_derivatives = &G::kinematics_derivatives;
      if constexpr (detail::has_joint_reactions<G>) d.joint_reactions = &G::joint_reactions;
      bool forward = true;
      if constexpr (requires { G::has_forward_dynamics; }) forward = G::has_forward_dynamics;
      if constexpr (detail::has_forward_dynamics<G>) {
        if (forward) d.forward_dynamics = &G::forward_dynamics;
      }
    }
  }
  return d;
}

}  // namespace symdyn::runtime
