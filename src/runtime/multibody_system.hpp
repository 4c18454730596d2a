#pragma once
// MultibodySystem: the equations of motion of a generated model plus force
// elements, as a DynamicSystem for integrators, statics and linearization.
//
// Residual (virtual power), for every coordinate j:
//   f_j = sum_i (m_i a_i - F_i).dv_i/dqd_j + (J_i dw_i + w_i x (J_i w_i) - M_i).dw_i/dqd_j - Q_j
// with J_i = R_i I_i R_i^T, F_i and M_i the applied forces and moments at G_i
// (gravity m_i g included in F_i) and Q_j the generalized forces of elements.
// Explicit form: M qdd = Q - h, solved by Cholesky (SpdSolver); a singular or
// indefinite M is a NumericError naming the time and the state. Where the
// generator emitted forward_dynamics (the articulated-body algorithm, linear
// in the bodies), the emitted source uses it instead, Q from the force
// elements first: qdd = forward_dynamics(tau = Q), without M; a failed pivot
// or a non-finite result goes the way of M, whose errors name the culprit.
// Likewise the residual is inverse_dynamics(qdd) - Q where it was emitted.
//
// Two sources of M and h (selectable, compare_sources() checks they agree):
//   emitted:   the generated equations, the default when the model has them.
//              One emitted call per evaluation gives M, h and exactly the
//              kinematics the force elements read (ForceElement::reads():
//              nothing, positions or velocities, with the partial velocities
//              that project their forces on bodies); without force elements,
//              M and h alone;
//   assembled: M_jk = sum_i m_i dv_ij.dv_ik + dw_ij.J_i dw_ik from the partial
//              velocities, h = f(qdd = 0) without applied forces but gravity
//              (EasyDyn's way, and the reference the emitted source is checked
//              against).
//
// Extra first-order states y (a motor current, a controller integral) have
// yd = e(t, q, qd, y) given by a callback; force elements read y from the
// state. Every value that crosses an API boundary is checked once: a
// non-finite q, qd, y, kinematic quantity read, load or result is a
// NumericError naming the time, the quantity and the body or coordinate (and
// the force element for loads).
//
// Closed loops (a model with implicit dependent parameters, loop_closure.hpp):
// the state is in the independent coordinates q (n = nindependent) only; each
// evaluation solves the implicit dependent parameters p and their rates,
// evaluates the tree in x = (q, p) and reduces it: M = Tᵀ·M_x·T,
// h = Tᵀ·(h_x + M_x·c), Q = Tᵀ·Q_x, the force elements seeing the tree's
// kinematics and the extended state. mass_matrix, bias_forces_*,
// applied_forces, energies, momentum and evaluate_kinematics take either the
// state in q (reduced, loops closed) or in x (the tree's). Jacobians are by
// central differences of the reduced residual.
//
// Not thread-safe: a system owns its workspace; use one system per thread.

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>
#include <symdyn/runtime/energy.hpp>
#include <symdyn/runtime/force_element.hpp>
#include <symdyn/runtime/loop_closure.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/spd_solver.hpp>
#include <symdyn/runtime/tree_solver.hpp>

namespace symdyn::runtime {

enum class EquationsSource { assembled, emitted };

// The forward dynamics and its derivatives at a state (MultibodySystem::dynamics_derivatives).
struct DynamicsDerivatives {
  Vector qdd;        // (nq)
  Matrix dqdd_dq;    // (nq x nq)
  Matrix dqdd_dqd;   // (nq x nq)
  Matrix dqdd_dtau;  // (nq x nq) M⁻¹, or empty unless asked for
};

class MultibodySystem : public DynamicSystem {
 public:
  // Throws ModelError when the model lacks the entry points the source needs
  // (velocities, accelerations, partial_velocities; mass_matrix and
  // bias_forces for the emitted source). Without a source: emitted when the
  // model has its equations of motion, else assembled.
  explicit MultibodySystem(Model model, std::optional<EquationsSource> source = std::nullopt);

  const Model& model() const { return model_; }
  // Sets a run-time model parameter (inertia re-validated: ModelError).
  void set_parameter(std::string_view name, double value) { model_.set_parameter(name, value); }
  EquationsSource source() const { return source_; }
  void set_source(EquationsSource source);
  // Whether the emitted source uses the model's recursive forward and inverse
  // dynamics where it has them (the default), or M and h.
  void set_recursive(bool recursive);
  bool recursive() const { return forward_ != nullptr || inverse_ != nullptr; }

  // Force elements, applied in the order added.
  void add(std::shared_ptr<const ForceElement> element);
  template <class E, class... Args>
  std::shared_ptr<E> add(Args&&... args) {
    auto e = std::make_shared<E>(std::forward<Args>(args)...);
    add(e);
    return e;
  }
  const std::vector<std::shared_ptr<const ForceElement>>& force_elements() const {
    return elements_;
  }

  // Extra states: names (m), initial values (m) and e(s, k, out) writing yd
  // (m) from the state and its kinematics up to `reads`.
  using ExtraEquations =
      std::function<void(const State& s, const Kinematics& k, Eigen::Ref<Vector> yd)>;
  void set_extra_states(std::vector<std::string> names, const Vector& initial, ExtraEquations e,
                        KinematicsLevel reads = KinematicsLevel::velocities);

  // The kinematics an evaluation computes: the most any force element or the
  // extra equations read.
  KinematicsLevel kinematics_level() const { return level_; }

  // The model's initial q and qd at t = 0, with the extra states' initial values
  // (with closed loops, the independent coordinates alone).
  State initial_state() const;

  // Closed loops: the state in the tree's coordinates x = (q, p), xd = (qd, pd),
  // p and pd solved to close the loops at s (given in q; assembly: the first
  // solve starts from the model's guesses, later ones from the last solution,
  // reset_loops() starts again from the guesses). The state itself without loops.
  State extended_state(const State& s);
  // The tree's accelerations xdd = T·qdd + c (nq) at s and qdd (n) in q; qdd itself without loops.
  Vector extended_accelerations(const State& s, const Vector& qdd);
  void reset_loops() { loops_.reset(); }
  // The implicit dependent parameters' guesses (ncon) the next solve (and each
  // after reset_loops()) starts from: the assembly branch. ModelError for a wrong size.
  void set_loop_guess(const Vector& p);

  // DynamicSystem
  int num_coordinates() const override { return model_.nindependent(); }
  int num_extra_states() const override { return static_cast<int>(extra_names_.size()); }
  std::string coordinate_name(int i) const override { return model_.q_names()[i]; }
  std::string extra_state_name(int i) const override { return extra_names_[i]; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override;
  void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f, Vector& g) override;
  // M = df/dqdd, C = df/dqd, K = df/dq at (s, qdd). Exact where the model was
  // emitted with inverse_dynamics_derivatives (and, with closed loops,
  // constraint_derivatives; the source is emitted): C
  // and K are dtau/dqd and dtau/dq (with M from inverse_dynamics_jacobians, one
  // call, where emitted) less the force elements' dQ/dqd and dQ/dq,
  // exact from the elements that give them (ForceElement::load_derivatives),
  // the others' part by central differences of their Q alone; otherwise M exact (from the
  // chosen source), C and K by central differences of the residual (relative
  // step 1e-6 with floor 1e-6). jacobian_method() says which, for run summaries.
  void jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K) override;
  bool exact_jacobians() const;
  std::string jacobian_method() const;
  // Whether the emitted derivatives are used where the model has them (the
  // default); false: central differences of the residual, as without them
  // (to compare the two on one model).
  void set_exact_jacobians(bool exact) { use_exact_jacobians_ = exact; }
  // Whether the force elements' own exact derivatives are used (the default); false: every
  // element's part by central differences of its Q (to compare the two).
  void set_exact_load_derivatives(bool exact) { use_exact_loads_ = exact; }
  // Where exact_jacobians() (and there are no extra states, whose equations
  // are not differentiated): -M⁻¹·K and -M⁻¹·C.
  bool exact_acceleration_derivatives(const State& s, const Vector& qdd, Matrix& dqdd_dq,
                                      Matrix& dqdd_dqd) override;

  // The forward dynamics qdd(q, qd, tau) at s and its derivatives, force
  // elements included, tau (nq) generalized forces added to theirs on the
  // coordinates (a control input; empty: none):
  //   dqdd/dq = -M⁻¹·K,  dqdd/dqd = -M⁻¹·C,  dqdd/dtau = M⁻¹
  // (K, C of jacobians() at qdd), by solves with M's factorization; M⁻¹ is
  // formed only with `with_input_matrix`. Exact as jacobians() is.
  void dynamics_derivatives(const State& s, DynamicsDerivatives& out,
                            bool with_input_matrix = false, const Vector& tau = Vector());

  // The pieces, each evaluated at the state s (nq x nq and nq).
  void mass_matrix(const State& s, Matrix& M);
  void mass_matrix_assembled(const State& s, Matrix& M);
  void mass_matrix_emitted(const State& s, Matrix& M);
  // h = inertia terms at qdd = 0 and gravity (the emitted bias_forces' meaning).
  void bias_forces_assembled(const State& s, Vector& h);
  void bias_forces_emitted(const State& s, Vector& h);
  // Generalized applied forces of the force elements (gravity excluded):
  // Q_j = sum_i F_i.dv_ij + M_i.dw_ij + Q_j.
  void applied_forces(const State& s, Vector& Q);

  Energies energies(const State& s);
  Momentum momentum(const State& s);
  // The wrench every body's joint (its motion relative to its reference body
  // or the ground) transmits onto it from its reference at s (docs/runtime.md):
  // reaction (6 x nbody) column i the force (N), then the moment (N·m) about
  // body i's joint point, in body i's axes, with the force elements' loads at
  // s and qdd its accelerations (computed by the first form). ModelError where
  // the model was emitted without joint_reactions; NumericError naming the
  // body whose reaction is not finite.
  // With closed loops and s, qdd in the independent coordinates, the tree's
  // joints of x = (q, p) at xdd = T·qdd + c, the closures' forces
  // (loop_reactions) applied to their bodies with the force elements' loads;
  // a ModelError for a loop given by its equations (its forces act on no
  // known body).
  void joint_reactions(const State& s, Matrix& reaction);
  void joint_reactions(const State& s, const Vector& qdd, Matrix& reaction);
  // Closed loops (docs/runtime.md): the multipliers λ (ncon) of the tree's
  // M_x·xdd + h_x = Q_x + g_xᵀ·λ at s and qdd (n each, xdd = T·qdd + c),
  // λ = g_p⁻ᵀ·(M_x·xdd + h_x - Q_x)_p; and each equation's loop reaction
  // (names: Model::loop_reaction_name): for a close_loop, the force (N) on its
  // body b from its body a at the closure point, along the global axis of the
  // equation (-λ: the gap is point_a - point_b); for a loop given by its
  // equations, λ. The first forms at the state's accelerations. ModelError
  // for a model without loops or a state not in the independent coordinates.
  void loop_multipliers(const State& s, const Vector& qdd, Vector& lambda);
  void loop_reactions(const State& s, Vector& reaction);
  void loop_reactions(const State& s, const Vector& qdd, Vector& reaction);

  // The kinematics and loads of the last evaluation.
  const Kinematics& kinematics() const { return k_; }
  const Loads& loads() const { return loads_; }

  // Cold: the model's reason why M (n x n, an iteration matrix built on it
  // too) is singular at s, when it knows one: an angle sequence at its
  // singular configuration (Model::singular_angle_sequence). For statics and
  // linearization, which meet M through DynamicSystem.
  std::optional<std::string> explain_singular(const State& s, const Matrix& M) const override;
  // Cold: an angle sequence within kAngleSequenceWarning of its singular configuration at s.
  std::optional<std::string> explain_near_singular(const State& s) const override;

  // Evaluates velocity-level kinematics and partial velocities at s into
  // kinematics() (checked for finite values).
  const Kinematics& evaluate_kinematics(const State& s);

  // Domain edges (Model::kDomainMargin): an evaluation at a state where the argument
  // of a dependent parameter's restricted function is within the margin of its edge is a
  // NumericError naming the parameter, the time and the state; check_step looks
  // for such a touch between the step's ends, along the cubic Hermite
  // interpolant of q from (q, qd) at both, and names the time and state it found:
  // sampled (five samples), then located by golden section between two samples
  // where an argument changes sign (a pole passed), or about a discrete local
  // minimum of the margin whose parabola through its neighbours comes below 1e-2 or
  // below half the lowest sample (a tangential dip between samples). With closed
  // loops, it looks the same way for a branch point (LoopClosure::kBranchPoint)
  // and a domain edge on that interpolant, the loops closed by a copy of the
  // closure (the next evaluation's start untouched) at three samples, th = 0 (the
  // last step's end, kept), 1/2 and 1; the smallest pivot of the equilibrated
  // g_p located where it dips so or det(g_p)'s sign differs between samples (a
  // branch crossed); refused naming the loop, the time and the state.
  void check_step(const State& from, const State& to) override;

  // Warnings of the evaluations since construction or clear_warnings(), each
  // cause once, with the time: the accelerations (or the residual's iteration
  // matrix) have lost more than half their digits to M's conditioning, where
  // the smallest pivot of its factorization is below kConditionWarning of its
  // diagonal, or an angle sequence's middle angle is within
  // kAngleSequenceWarning rad of its singular value (its pivot falls as the
  // square of that distance; this check is also made where the accelerations
  // come from the recursive forward dynamics, without M).
  static constexpr double kConditionWarning = 1e-8;
  static constexpr double kAngleSequenceWarning = 1e-4;
  const std::vector<std::string>& warnings() const { return warnings_; }
  void clear_warnings();

 private:
  void check_state(const State& s) const;
  // Closed loops: whether s is in the independent coordinates (to be
  // reduced), and the extended state closing the loops at it (a checked state).
  bool reduces(const State& s) const {
    return model_.has_loops() && s.q.size() == model_.nindependent();
  }
  const State& close(const State& s);
  const State& close_with_accelerations(const State& s, const Vector& qdd);  // and xdd_
  const State& extended(const State& s);                                     // checked, then closed
  void check_independent(const State& s) const;
  void loop_accelerations(const State& s, Vector& qdd, Vector& yd);
  // joint_reactions() of a state in the independent coordinates.
  void loop_joint_reactions(const State& s, const Vector& qdd, Matrix& reaction);
  // The loads of the closures' forces λ at the closed state x onto its bodies (k_ at x).
  void add_closure_loads(const State& x, const Vector& lambda);
  void check_reactions(const State& s, const Matrix& reaction) const;
  // The rows of each p column of the tree's M_x that can hold a nonzero:
  // rows[start[k]..start[k + 1]) for column nindependent + k.
  struct Coupling {
    std::vector<int> start, rows;
  };
  void find_coupling(const Matrix& A, Coupling& coupling);
  void find_emitted_coupling();
  // The emitted source's coupling (found once) where `emitted`, else A's.
  const Coupling& coupling_of(const Matrix& A, bool emitted);
  // Tᵀ·A·T and Tᵀ·(b + A·c) of the tree's A and b (A's coupling given, or found).
  void reduce(const Matrix& A, const Coupling& coupling, Matrix& out);
  void reduce(const Matrix& A, Matrix& out);
  void reduce(const Vector& b, const Matrix& A, Vector& out);
  void reduce(const Vector& b, Vector& out);  // Tᵀ·b
  void tree_residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f, Vector& g);
  // Names what is wrong with a state check_state() refused.
  [[noreturn, gnu::cold, gnu::noinline]] void state_error(const State& s) const;
  // Throws naming the first body with a non-finite quantity among those
  // evaluated: up to `level` (with partial velocities from positions up),
  // and a, dw with accelerations.
  void check_kinematics(const State& s, KinematicsLevel level, bool accelerations) const;
  void update_level();
  // M_, h_ and (with force elements) elements_Q_ at s, kinematics up to level_.
  void evaluate_equations(const State& s);
  void apply_elements(const State& s);
  // sum_i F_i.dv_ij + M_i.dw_ij + Q_j of the current loads and kinematics.
  void project_loads(Vector& Q) const;
  // f of the assembled residual from the current kinematics (with a, dw) and
  // loads; with_gravity adds the weights to the applied forces.
  void assemble_residual(Vector& f, bool with_gravity, bool with_loads) const;
  void assemble_mass_matrix(Matrix& M);
  // The right-hand side of M qdd = rhs (M in M_) of a checked state, but for the
  // emitted equations without force elements (accelerations() inline).
  void accelerations_rhs(const State& s, Vector& qdd);
  // qdd by the emitted forward dynamics with the force elements' loads or the
  // kinematics read (the state checked first); false when a pivot failed or qdd
  // is not finite (the caller then takes the way of M).
  bool recursive_accelerations(const State& s, Vector& qdd);
  // qdd of a state by M's factorization (the way of M), qdd checked.
  void mass_matrix_accelerations(const State& s, Vector& qdd);
  // accelerations(), by the way of M even where the recursive one is emitted
  // when by_mass_matrix (M is needed factored anyway: dynamics_derivatives).
  void accelerations(const State& s, Vector& qdd, Vector& yd, bool by_mass_matrix);
  // Kinematics up to level_ (for force elements and extra equations) and,
  // with force elements, their generalized forces into elements_Q_.
  void evaluate_elements(const State& s);
  // The force elements' generalized forces into elements_Q_, from the kinematics up to level_.
  void elements_generalized_forces(const State& s);
  // Out of the hot path: what is wrong when M_ was refused or the accelerations are
  // not finite, the state first.
  [[noreturn, gnu::cold, gnu::noinline]] void mass_matrix_refused(const State& s) const;
  [[noreturn, gnu::cold, gnu::noinline]] void accelerations_not_finite(const State& s) const;
  // Names why `result` (the accelerations or the residual) is not finite.
  [[noreturn, gnu::cold, gnu::noinline]] void explain_non_finite(
      const State& s, const char* result = "accelerations are") const;
  // Throws naming the dependent parameter out of its domain at s, if any.
  [[gnu::cold, gnu::noinline]] void throw_domain_error(const State& s) const;
  std::string describe(const State& s) const;
  void jacobians_by_differences(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K);
  // dqdd/dq and dqdd/dqd from jacobians() at (s, qdd): -M⁻¹·K and -M⁻¹·C by
  // solves, by tree_solver_ where M has a tree's sparsity (tree_factored_), else
  // by solver_; with `factored`, M at s is in *factored and solver_ holds it
  // already (exact Jacobians only).
  void acceleration_derivatives(const State& s, const Vector& qdd, Matrix& dqdd_dq,
                                Matrix& dqdd_dqd, const Matrix* factored = nullptr);
  // The exact C and K of jacobians(), and M where asked (from the same emitted
  // call, inverse_dynamics_jacobians, where the model has it): C and K
  // column-major, or row-major as emitted (RowMajorMatrix, for the solves of
  // acceleration_derivatives()).
  template <class Storage>
  void exact_damping_stiffness(const State& s, const Vector& qdd, Storage& C, Storage& K,
                               Matrix* M = nullptr);
  // With closed loops: the reduced M, C, K from the tree's at the extended
  // state and the loops' derivatives (loop_closure.hpp).
  void exact_loop_jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K);
  template <class Storage>
  void subtract_load_derivatives(const State& s, Storage& C, Storage& K);
  // Whether the element's part of jacobians() is exact (else differenced).
  bool exact_loads(const ForceElement& e) const;
  void evaluate_elements_kinematics(const State& s);
  void differenced_forces(const State& s, Vector& Q);
  // Q of those elements from the kinematics in k_ (not evaluated).
  void differenced_loads(const State& s, Vector& Q);
  // k_'s v_i, w_i at qd + h·e_j: base_v_, base_w_ (at qd) + h·dv_i/dqd_j, h·dw_i/dqd_j.
  void shift_velocities(int j, double h);
  [[noreturn, gnu::cold, gnu::noinline]] void derivatives_not_finite(const State& s) const;
  // Refuses s (a full state, checked) within Model::kDomainMargin of a domain edge.
  void check_domain_margin(const State& s) {
    if (model_.has_domain_margins()) check_domain_margin_cold(s);
  }
  void check_domain_margin_cold(const State& s);
  [[noreturn, gnu::cold, gnu::noinline]] void domain_margin_refused(const State& s,
                                                                    const Model::DomainMargin& m,
                                                                    const char* where = "") const;
  // The smallest margin along the step's interpolant, its time and state in edge_state_.
  Model::DomainMargin closest_approach(const State& from, const State& to);
  void check_loop_step(const State& from, const State& to);
  [[noreturn, gnu::cold, gnu::noinline]] void loop_domain_margin_refused(
      const State& from, const State& to, double th, const Model::DomainMargin& m);
  void interpolate_step(const State& from, const State& to, double th, State& out) const;
  // Conditioning warnings (see warnings()), after an evaluation at s; M_ factored
  // in solver_ when `factored`.
  void watch_conditioning(const State& s, bool factored) {
    if (conditioning_warned_) return;
    const bool ill = factored && solver_.smallest_pivot_ratio() < kConditionWarning;
    if (ill || !model_.angle_sequences().empty()) watch_angle_sequences(s, ill);
  }
  void watch_angle_sequences(const State& s, bool ill);

  Model model_;
  LoopClosure loops_;                     // with closed loops
  State closed_;                          // the extended state of the last close()
  Vector xdd_, rhs_x_;                    // (nq) the tree's accelerations and right-hand side
  Matrix tree_M_;                         // (nq x nq) a tree's matrix
  Matrix AT_;                             // (nq x n) A·T in reduce()
  Coupling emitted_coupling_, coupling_;  // the emitted M_x's (found once), a call's
  bool has_emitted_coupling_ = false;
  Vector tree_v_;  // (nq)
  EquationsSource source_;
  std::vector<std::shared_ptr<const ForceElement>> elements_;
  std::vector<std::string> extra_names_;
  Vector extra_initial_;
  ExtraEquations extra_;
  KinematicsLevel extra_reads_ = KinematicsLevel::none;
  KinematicsLevel level_ = KinematicsLevel::none;
  DynamicsFn dynamics_ =
      nullptr;  // the emitted dynamics() when level_ is none: no dispatch per call
  ForwardDynamicsFn forward_ = nullptr;  // the emitted recursive ones, when used
  InverseDynamicsFn inverse_ = nullptr;
  // forward_ when the emitted source has nothing else to evaluate (no force element,
  // no kinematics read): accelerations() calls it inline, no dispatch per call.
  ForwardDynamicsFn forward_without_elements_ = nullptr;
  bool use_exact_jacobians_ = true;
  bool use_exact_loads_ = true;
  bool mass_factored_ = false;  // solver_ holds M at the state of the last accelerations()

  // Workspace: sized at construction, reused by every evaluation.
  Kinematics k_;
  Loads loads_;
  Vector zero_, assembled_residual_, elements_Q_, h_;
  Matrix M_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> dw_inertia_;  // (nq x 3)
  SpdSolver solver_;
  TreeSolver tree_solver_;      // dynamics_derivatives()' solves where M is tree-sparse
  bool tree_factored_ = false;  // tree_solver_ holds M of the last acceleration_derivatives()
  State jacobian_state_;        // jacobians(): the shifted state,
  Vector jacobian_yd_, jacobian_fp_, jacobian_fm_, jacobian_g_;  // and its residuals
  Matrix derivative_M_;                                          // dynamics_derivatives(): M
  RowMajorMatrix stiffness_rows_, damping_rows_;  // acceleration_derivatives(): K and C as emitted
  Matrix load_dq_, load_dqd_;                     // the force elements' dQ/dq, dQ/dqd
  Matrix tree_K_, tree_C_,
      tree_KT_;  // exact_loop_jacobians(): the tree's K_x, C_x (nq x nq), a product (nq x n)
  KinematicsDerivatives dk_;                // where the model has them
  std::vector<double> base_v_, base_w_;     // k_'s v, w at the state differenced (nbody x 3)
  std::vector<double> domain_arguments_;    // (3·ndomain) Model::smallest_domain_margin's
  std::vector<double> previous_arguments_;  // (3·ndomain) closest_approach(): the last sample's
  State edge_state_;                        // check_step(): a state within the step
  LoopClosure probe_loops_;                 // check_loop_step(): loops_ at the step's end, moved
  Vector probe_x_;                          // (nq) and its solutions
  // check_loop_step(): the measures at a point of a step's interpolant (the margin
  // with domain margins), and the last step's end (its time, q and the measures there)
  struct LoopSample {
    LoopClosure::Singularity branch;
    Model::DomainMargin domain;
  };
  double probed_end_t_ = std::numeric_limits<double>::quiet_NaN();
  Vector probed_end_q_;
  LoopSample probed_end_;
  std::vector<std::string> warnings_;
  bool conditioning_warned_ = false;  // the conditioning warning is given once
};

// Largest absolute differences between the assembled and the emitted mass
// matrix and bias forces at s (ModelError if the model has no emitted ones).
struct SourceComparison {
  double mass_matrix = 0.0;
  double bias_forces = 0.0;
};
SourceComparison compare_sources(MultibodySystem& system, const State& s);

}  // namespace symdyn::runtime
