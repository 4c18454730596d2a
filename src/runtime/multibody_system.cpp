#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::runtime {

MultibodySystem::MultibodySystem(Model model, std::optional<EquationsSource> source)
    : model_(std::move(model)) {
  const bool emitted = model_.has_equations_of_motion();
  source_ = source.value_or(emitted ? EquationsSource::emitted : EquationsSource::assembled);
  const char* needed[] = {"velocities", "accelerations", "partial_velocities"};
  const bool present[] = {model_.has_velocities(), model_.has_accelerations(),
                          model_.has_partial_velocities()};
  for (int n = 0; n < 3; ++n) {
    if (!present[n]) {
      throw ModelError(fmt::format("model '{}': a multibody system needs the entry point '{}'",
                                   model_.name(), needed[n]));
    }
  }
  set_source(source_);
  set_recursive(true);
  update_level();
  const int nq = model_.nq();
  k_ = model_.make_kinematics();
  loads_ = Loads(nq, model_.nbody());
  zero_ = Vector::Zero(nq);
  assembled_residual_.resize(nq);
  elements_Q_ = Vector::Zero(nq);  // stays zero without force elements
  h_ = Vector::Zero(nq);
  M_ = Matrix::Zero(nq, nq);
  dw_inertia_.resize(nq, 3);
  solver_ = SpdSolver(num_coordinates());
  tree_solver_ = TreeSolver(num_coordinates());
  if (model_.has_loops()) loops_ = LoopClosure(model_);
  find_emitted_coupling();
  if (model_.has_kinematics_derivatives()) dk_ = model_.make_kinematics_derivatives();
  base_v_.resize(static_cast<std::size_t>(3 * model_.nbody()));
  base_w_.resize(static_cast<std::size_t>(3 * model_.nbody()));
  domain_arguments_.resize(Model::kDomainValues *
                           static_cast<std::size_t>(model_.num_domain_checks()));
  previous_arguments_.resize(domain_arguments_.size());
  edge_state_ = initial_state();  // sized: check_step allocates nothing
}

void MultibodySystem::set_source(EquationsSource source) {
  if (source == EquationsSource::emitted && !model_.has_equations_of_motion()) {
    throw ModelError(fmt::format(
        "model '{}': the emitted source needs mass_matrix and bias_forces, which were not emitted",
        model_.name()));
  }
  source_ = source;
  update_level();
}

void MultibodySystem::set_recursive(bool recursive) {
  forward_ = recursive ? model_.emitted_forward_dynamics() : nullptr;
  inverse_ = recursive ? model_.emitted_inverse_dynamics() : nullptr;
  update_level();
}

void MultibodySystem::add(std::shared_ptr<const ForceElement> element) {
  if (!element) throw ModelError("a null force element was added");
  elements_.push_back(std::move(element));
  update_level();
}

void MultibodySystem::update_level() {
  level_ = extra_reads_;
  for (const auto& e : elements_) level_ = std::max(level_, e->reads());
  dynamics_ = level_ == KinematicsLevel::none ? model_.emitted_dynamics() : nullptr;
  const bool alone =
      source_ == EquationsSource::emitted && level_ == KinematicsLevel::none && elements_.empty();
  forward_without_elements_ = alone ? forward_ : nullptr;
}

void MultibodySystem::set_extra_states(std::vector<std::string> names, const Vector& initial,
                                       ExtraEquations e, KinematicsLevel reads) {
  if (initial.size() != static_cast<Eigen::Index>(names.size())) {
    throw ModelError(fmt::format("{} extra states named but {} initial values given", names.size(),
                                 initial.size()));
  }
  if (!e && !names.empty()) throw ModelError("extra states need their equations");
  extra_names_ = std::move(names);
  extra_initial_ = initial;
  extra_ = std::move(e);
  extra_reads_ = extra_ ? reads : KinematicsLevel::none;
  edge_state_.y.resize(extra_initial_.size());
  update_level();
}

State MultibodySystem::initial_state() const {
  State s = model_.initial_state();
  s.q.conservativeResize(num_coordinates());
  s.qd.conservativeResize(num_coordinates());
  s.y = extra_initial_;
  return s;
}

State MultibodySystem::extended_state(const State& s) {
  if (!model_.has_loops()) return s;
  return extended(s);
}

Vector MultibodySystem::extended_accelerations(const State& s, const Vector& qdd) {
  if (!model_.has_loops()) return qdd;
  extended(s);
  if (qdd.size() != num_coordinates()) {
    throw ModelError(fmt::format("model '{}': {} accelerations given; expected {}", model_.name(),
                                 qdd.size(), num_coordinates()));
  }
  Vector xdd = loops_.c();
  xdd.noalias() += loops_.T() * qdd;
  return xdd;
}

void MultibodySystem::set_loop_guess(const Vector& p) {
  if (p.size() != model_.ncon() || !p.allFinite()) {
    throw ModelError(fmt::format("model '{}': the loops' guess must be {} finite values ({} given)",
                                 model_.name(), model_.ncon(), p.size()));
  }
  loops_.set_guess(p);
}

const State& MultibodySystem::extended(const State& s) {
  check_independent(s);
  return close(s);
}

const State& MultibodySystem::close(const State& s) {
  closed_.t = s.t;
  loops_.close(model_, s.t, s.q, s.qd, closed_.q, closed_.qd);
  closed_.y = s.y;
  return closed_;
}

void MultibodySystem::check_independent(const State& s) const {
  const Eigen::Index n = num_coordinates(), ny = num_extra_states();
  if (s.q.size() != n || s.qd.size() != n || s.y.size() != ny) {
    throw ModelError(fmt::format(
        "model '{}': a state with {} q, {} qd, {} y given; expected {}, {}, {} (the independent "
        "coordinates {} of its closed loops)",
        model_.name(), s.q.size(), s.qd.size(), s.y.size(), n, n, ny,
        fmt::join(std::vector<std::string>(model_.q_names().begin(), model_.q_names().begin() + n),
                  ", ")));
  }
  if (s.q.allFinite() && s.qd.allFinite() && s.y.allFinite() && std::isfinite(s.t)) return;
  // The extended state's check names the culprit (p is not solved: the guesses stand in).
  State x = model_.initial_state();
  x.t = s.t;
  x.q.head(n) = s.q;
  x.qd.head(n) = s.qd;
  x.y = s.y;
  state_error(x);
}

// The rows of each p column of A (nq x nq) holding a nonzero: this call's.
void MultibodySystem::find_coupling(const Matrix& A, Coupling& coupling) {
  const Eigen::Index n = model_.nindependent(), m = model_.ncon();
  coupling.start.assign(static_cast<std::size_t>(m + 1), 0);
  coupling.rows.clear();
  for (Eigen::Index k = 0; k < m; ++k) {
    const double* a = A.col(n + k).data();
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      if (a[i] != 0.0) coupling.rows.push_back(static_cast<int>(i));
    }
    coupling.start[static_cast<std::size_t>(k + 1)] = static_cast<int>(coupling.rows.size());
  }
}

// The emitted M_x's structural coupling: the entries of its p columns that are
// not the constant 0 (nonzero, or NaN, at NaN coordinates, rates and
// parameters: any entry that depends on them), with those nonzero at the
// model's initial state (should an emitted function not carry NaN through).
void MultibodySystem::find_emitted_coupling() {
  const DynamicsFn dynamics = model_.emitted_dynamics();
  if (!model_.has_loops() || dynamics == nullptr) return;
  const int nq = model_.nq();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vector any = Vector::Constant(nq, nan);
  const std::vector<double> any_parameters(model_.parameters().size(), nan);
  Matrix probe = Matrix::Zero(nq, nq), at_initial = Matrix::Zero(nq, nq);
  Vector h(nq);
  dynamics(nan, any.data(), any.data(), any_parameters.data(), probe.data(), h.data());
  const State x = model_.initial_state();
  dynamics(x.t, x.q.data(), x.qd.data(), model_.parameters().data(), at_initial.data(), h.data());
  probe = (probe.array() != 0.0 || at_initial.array() != 0.0).cast<double>();
  find_coupling(probe, emitted_coupling_);
  has_emitted_coupling_ = true;
}

// T = [I; P] and c = [0; c_p]: the products with their identity and zero
// blocks left out, by plain loops (Eigen's set-up costs more at these sizes).
// A tree's A = M_x is zero between coordinates of different branches (a
// Stewart platform's legs): A·T = A_q + A_p·P adds P's row k only at the rows
// of A_p's column k that `coupling` lists. Tᵀ·A·T is symmetric: its lower
// triangle is computed, the upper copied.
void MultibodySystem::reduce(const Matrix& A, const Coupling& coupling, Matrix& out) {
  const Eigen::Index n = model_.nindependent(), m = model_.ncon(), rows = A.rows();
  const double* T = loops_.T().data();  // (rows x n) column-major, P = its rows n..
  AT_ = A.leftCols(n);
  double* AT = AT_.data();
  for (Eigen::Index k = 0; k < m; ++k) {
    const double* a = A.col(n + k).data();
    for (int e = coupling.start[static_cast<std::size_t>(k)];
         e < coupling.start[static_cast<std::size_t>(k + 1)]; ++e) {
      const int i = coupling.rows[static_cast<std::size_t>(e)];
      for (Eigen::Index j = 0; j < n; ++j) AT[i + j * rows] += a[i] * T[n + k + j * rows];
    }
  }
  // Tᵀ·(A·T) = (A·T)_q + Pᵀ·(A·T)_p
  out.resize(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j; i < n; ++i) {
      const double* p = T + i * rows + n;
      const double* b = AT + j * rows + n;
      double sum = AT[i + j * rows];
      for (Eigen::Index k = 0; k < m; ++k) sum += p[k] * b[k];
      out(i, j) = out(j, i) = sum;
    }
  }
}

void MultibodySystem::reduce(const Matrix& A, Matrix& out) {
  reduce(A, coupling_of(A, false), out);
}

const MultibodySystem::Coupling& MultibodySystem::coupling_of(const Matrix& A, bool emitted) {
  if (emitted && has_emitted_coupling_) return emitted_coupling_;
  find_coupling(A, coupling_);
  return coupling_;
}

void MultibodySystem::reduce(const Vector& b, const Matrix& A, Vector& out) {
  xdd_ = b;
  xdd_.noalias() += A.rightCols(model_.ncon()) * loops_.c().tail(model_.ncon());
  reduce(xdd_, out);
}

void MultibodySystem::reduce(const Vector& b, Vector& out) {
  const Eigen::Index n = model_.nindependent(), m = model_.ncon();
  out = b.head(n);
  out.noalias() += loops_.T().bottomRows(m).transpose() * b.tail(m);
}

std::string MultibodySystem::describe(const State& s) const {
  std::string out = "q = (";
  const auto n = static_cast<int>(std::min<Eigen::Index>(s.q.size(), model_.nq()));
  for (int j = 0; j < n; ++j) {
    out += fmt::format("{}{} = {}", j ? ", " : "", model_.q_names()[j], s.q(j));
  }
  out += "), qd = (";
  for (int j = 0; j < std::min<int>(n, static_cast<int>(s.qd.size())); ++j) {
    out += fmt::format("{}{}", j ? ", " : "", s.qd(j));
  }
  return out + ")";
}

namespace {

// x·0 is 0 for a finite x and NaN otherwise: one pass without branches, in
// eight sums, so that the additions are not one chain of dependent ones.
bool all_finite(const double* x, Eigen::Index n) {
  double zero[8] = {};
  Eigen::Index i = 0;
  for (; i + 8 <= n; i += 8) {
    for (int k = 0; k < 8; ++k) zero[k] += x[i + k] * 0.0;
  }
  for (; i < n; ++i) zero[0] += x[i] * 0.0;
  double sum = 0.0;
  for (const double z : zero) sum += z;
  return sum == 0.0;
}

// The state's values and the accelerations r (nq, as s.q) in one pass.
bool all_finite(const State& s, const Vector& r) {
  double zero = s.t * 0.0;
  const double *q = s.q.data(), *qd = s.qd.data(), *x = r.data();
  for (Eigen::Index j = 0; j < r.size(); ++j) zero += (q[j] * 0.0 + qd[j] * 0.0) + x[j] * 0.0;
  for (Eigen::Index j = 0; j < s.y.size(); ++j) zero += s.y[j] * 0.0;
  return zero == 0.0;
}

}  // namespace

void MultibodySystem::check_state(const State& s) const {
  const Eigen::Index nq = model_.nq();
  const auto ny = static_cast<Eigen::Index>(extra_names_.size());
  if (s.q.size() != nq || s.qd.size() != nq || s.y.size() != ny) state_error(s);
  if (!(all_finite(&s.t, 1) && all_finite(s.q.data(), nq) && all_finite(s.qd.data(), nq) &&
        all_finite(s.y.data(), ny))) {
    state_error(s);
  }
}

void MultibodySystem::state_error(const State& s) const {
  const int nq = model_.nq();
  if (s.q.size() != nq || s.qd.size() != nq || s.y.size() != num_extra_states()) {
    throw ModelError(fmt::format(
        "model '{}': a state with {} q, {} qd, {} y given; expected {}, {}, {}", model_.name(),
        s.q.size(), s.qd.size(), s.y.size(), nq, nq, num_extra_states()));
  }
  if (!std::isfinite(s.t)) throw NumericError(fmt::format("time is not finite ({})", s.t));
  for (int j = 0; j < nq; ++j) {
    if (!std::isfinite(s.q(j)) || !std::isfinite(s.qd(j))) {
      throw NumericError(fmt::format("t = {}: coordinate '{}' is not finite (q = {}, qd = {})", s.t,
                                     model_.q_names()[j], s.q(j), s.qd(j)));
    }
  }
  for (int j = 0; j < num_extra_states(); ++j) {
    if (!std::isfinite(s.y(j))) {
      throw NumericError(
          fmt::format("t = {}: extra state '{}' is not finite ({})", s.t, extra_names_[j], s.y(j)));
    }
  }
  throw std::logic_error("MultibodySystem::state_error called on a valid state");
}

void MultibodySystem::check_kinematics(const State& s, KinematicsLevel level,
                                       bool accelerations) const {
  using enum KinematicsLevel;
  if (level == none) return;
  if (level == velocities && k_.all_finite(accelerations)) return;
  // Error path (or positions only): find the body and the quantity to name.
  struct Quantity {
    const char* name;
    bool finite;
  };
  const bool rates = level == velocities;
  for (int i = 0; i < model_.nbody(); ++i) {
    const Quantity qs[] = {
        {"rotation R", k_.R(i).allFinite()},
        {"position x", k_.x(i).allFinite()},
        {"velocity v", !rates || k_.v(i).allFinite()},
        {"angular velocity w", !rates || k_.w(i).allFinite()},
        {"acceleration a", !accelerations || k_.a(i).allFinite()},
        {"angular acceleration dw", !accelerations || k_.dw(i).allFinite()},
        {"partial velocity dv/dqd", k_.dv_dqd(i).allFinite()},
        {"partial angular velocity dw/dqd", k_.dw_dqd(i).allFinite()},
    };
    for (const Quantity& q : qs) {
      if (!q.finite) {
        throw_domain_error(s);
        throw NumericError(fmt::format("t = {}: body '{}': {} is not finite at {}", s.t,
                                       model_.body_names()[i], q.name, describe(s)));
      }
    }
  }
}

void MultibodySystem::apply_elements(const State& s) {
  loads_.clear();
  for (const auto& e : elements_) e->apply(s, k_, loads_);
  if (level_ == KinematicsLevel::none && loads_.on_bodies()) {
    // Without partial velocities a force on a body cannot be projected.
    for (const auto& e : elements_) {
      Loads one(model_.nq(), model_.nbody());
      e->apply(s, k_, one);
      if (one.on_bodies()) {
        throw ModelError(
            fmt::format("{} applies a force on a body but declares that it reads no kinematics "
                        "(ForceElement::reads() must be positions or velocities)",
                        e->name()));
      }
    }
  }
  if (loads_.F.allFinite() && loads_.M.allFinite() && loads_.Q.allFinite()) return;
  // Error path: find the element and the body or coordinate to name.
  for (const auto& e : elements_) {
    Loads one(model_.nq(), model_.nbody());
    e->apply(s, k_, one);
    for (int i = 0; i < model_.nbody(); ++i) {
      if (!one.F.col(i).allFinite() || !one.M.col(i).allFinite()) {
        throw NumericError(fmt::format("t = {}: {}: force or moment on body '{}' is not finite",
                                       s.t, e->name(), model_.body_names()[i]));
      }
    }
    for (int j = 0; j < model_.nq(); ++j) {
      if (!std::isfinite(one.Q(j))) {
        throw NumericError(
            fmt::format("t = {}: {}: generalized force on coordinate '{}' is not finite", s.t,
                        e->name(), model_.q_names()[j]));
      }
    }
  }
  throw NumericError(fmt::format("t = {}: a load is not finite", s.t));
}

void MultibodySystem::project_loads(Vector& Q) const {
  Q = loads_.Q;
  for (int i = 0; i < model_.nbody(); ++i) {
    // Most bodies carry no load (amru5: 6 feet of 49 bodies); the partial
    // velocities are finite (check_kinematics), so skipping adds nothing.
    if (!loads_.F.col(i).isZero(0.0)) Q.noalias() += k_.dv_dqd(i) * loads_.F.col(i);
    if (!loads_.M.col(i).isZero(0.0)) Q.noalias() += k_.dw_dqd(i) * loads_.M.col(i);
  }
}

void MultibodySystem::assemble_residual(Vector& f, bool with_gravity, bool with_loads) const {
  f.setZero();
  const Vec3& g = model_.gravity();
  for (int i = 0; i < model_.nbody(); ++i) {
    const double m = model_.mass(i);
    const Mat3 J = model_.global_inertia(i, k_);
    const Vec3 w = k_.w(i);
    // inertia force m a - F and moment J dw + w x (J w) - M
    Vec3 force = m * k_.a(i);
    Vec3 moment = J * k_.dw(i) + w.cross(J * w);
    if (with_gravity) force -= m * g;
    if (with_loads) {
      force -= loads_.F.col(i);
      moment -= loads_.M.col(i);
    }
    f.noalias() += k_.dv_dqd(i) * force;
    f.noalias() += k_.dw_dqd(i) * moment;
  }
  if (with_loads) f -= loads_.Q;
}

void MultibodySystem::assemble_mass_matrix(Matrix& M) {
  // M_jk = sum_i m_i dv_ij.dv_ik + dw_ij.J_i dw_ik
  M.setZero();
  for (int i = 0; i < model_.nbody(); ++i) {
    const Mat3 J = model_.global_inertia(i, k_);
    M.noalias() += model_.mass(i) * k_.dv_dqd(i) * k_.dv_dqd(i).transpose();
    dw_inertia_.noalias() = k_.dw_dqd(i) * J;
    M.noalias() += dw_inertia_ * k_.dw_dqd(i).transpose();
  }
}

const Kinematics& MultibodySystem::evaluate_kinematics(const State& s) {
  if (reduces(s)) return evaluate_kinematics(extended(s));
  check_state(s);
  model_.velocities(s.t, s.q.data(), s.qd.data(), k_);
  model_.partial_velocities(s.t, s.q.data(), k_);
  check_kinematics(s, KinematicsLevel::velocities, false);
  return k_;
}

void MultibodySystem::mass_matrix(const State& s, Matrix& M) {
  if (reduces(s)) {
    const State& x = extended(s);
    mass_matrix(x, tree_M_);
    reduce(tree_M_, M);
    return;
  }
  if (source_ == EquationsSource::emitted) {
    mass_matrix_emitted(s, M);
  } else {
    mass_matrix_assembled(s, M);
  }
}

void MultibodySystem::mass_matrix_assembled(const State& s, Matrix& M) {
  if (reduces(s)) {
    const State& x = extended(s);
    mass_matrix_assembled(x, tree_M_);
    reduce(tree_M_, M);
    return;
  }
  check_state(s);
  model_.positions(s.t, s.q.data(), k_);
  model_.partial_velocities(s.t, s.q.data(), k_);
  check_kinematics(s, KinematicsLevel::positions, false);
  M.resize(model_.nq(), model_.nq());
  assemble_mass_matrix(M);
}

void MultibodySystem::mass_matrix_emitted(const State& s, Matrix& M) {
  if (reduces(s)) {
    const State& x = extended(s);
    mass_matrix_emitted(x, tree_M_);
    reduce(tree_M_, M);
    return;
  }
  check_state(s);
  // The emitted M is row-major and symmetric, so its column-major layout is
  // the same array.
  M.resize(model_.nq(), model_.nq());
  model_.mass_matrix(s.t, s.q.data(), M.data());
}

void MultibodySystem::bias_forces_assembled(const State& s, Vector& h) {
  if (reduces(s)) {
    const State& x = extended(s);
    mass_matrix_assembled(x, tree_M_);
    bias_forces_assembled(x, tree_v_);
    reduce(tree_v_, tree_M_, h);
    return;
  }
  check_state(s);
  model_.accelerations(s.t, s.q.data(), s.qd.data(), zero_.data(), k_);
  model_.partial_velocities(s.t, s.q.data(), k_);
  check_kinematics(s, KinematicsLevel::velocities, true);
  h.resize(model_.nq());
  assemble_residual(h, true, false);
}

void MultibodySystem::bias_forces_emitted(const State& s, Vector& h) {
  if (reduces(s)) {
    const State& x = extended(s);
    mass_matrix_emitted(x, tree_M_);
    bias_forces_emitted(x, tree_v_);
    reduce(tree_v_, tree_M_, h);
    return;
  }
  check_state(s);
  h.resize(model_.nq());
  model_.bias_forces(s.t, s.q.data(), s.qd.data(), h.data());
}

void MultibodySystem::applied_forces(const State& s, Vector& Q) {
  if (reduces(s)) {
    const State& x = extended(s);
    applied_forces(x, tree_v_);
    reduce(tree_v_, Q);
    return;
  }
  evaluate_kinematics(s);
  apply_elements(s);
  Q.resize(model_.nq());
  project_loads(Q);
}

void MultibodySystem::evaluate_equations(const State& s) {
  model_.dynamics(s.t, s.q.data(), s.qd.data(), level_, M_.data(), h_.data(), k_);
  elements_generalized_forces(s);
}

void MultibodySystem::elements_generalized_forces(const State& s) {
  if (elements_.empty()) return;
  if (!k_.finite_up_to(level_)) check_kinematics(s, level_, false);
  apply_elements(s);
  project_loads(elements_Q_);
}

void MultibodySystem::mass_matrix_refused(const State& s) const {
  check_state(s);  // a non-finite state first: it is the cause
  if (!M_.allFinite()) explain_non_finite(s);
  const auto sequence = model_.singular_angle_sequence(s.q.data(), M_);
  throw NumericError(fmt::format(
      "t = {}: mass matrix is singular or indefinite: {} (pivot {:.3g} of its diagonal) at {}", s.t,
      sequence ? *sequence
               : mass_matrix_singularity(M_, [this](int j) { return model_.q_names()[j]; }),
      solver_.smallest_pivot_ratio(), describe(s)));
}

void MultibodySystem::accelerations_not_finite(const State& s) const {
  check_state(s);  // a non-finite state first: it is the cause
  explain_non_finite(s);
}

std::optional<std::string> MultibodySystem::explain_singular(const State& s,
                                                             const Matrix& M) const {
  if (s.q.size() != model_.nq()) return std::nullopt;
  return model_.singular_angle_sequence(s.q.data(), M);
}

std::optional<std::string> MultibodySystem::explain_near_singular(const State& s) const {
  if (s.q.size() != model_.nq()) return std::nullopt;
  return model_.angle_sequence_near_singular(s.q.data(), kAngleSequenceWarning);
}

// A dependent parameter out of its domain is the first suspect: it makes
// everything after it NaN (rotations, M, h), which would otherwise be named.
void MultibodySystem::throw_domain_error(const State& s) const {
  if (const auto what = model_.domain_error(s.t, s.q.data())) {
    throw NumericError(fmt::format("t = {}: {} at {}", s.t, *what, describe(s)));
  }
}

void MultibodySystem::check_domain_margin_cold(const State& s) {
  const Model::DomainMargin m =
      model_.smallest_domain_margin(s.t, s.q.data(), domain_arguments_.data());
  if (m.margin < Model::kDomainMargin) domain_margin_refused(s, m);
}

void MultibodySystem::domain_margin_refused(const State& s, const Model::DomainMargin& m,
                                            const char* where) const {
  if (!(m.margin > 0.0)) throw_domain_error(s);  // outside, or at the edge: its own words
  throw NumericError(fmt::format("t = {}: {}{} at {}", s.t,
                                 model_.describe_domain_margin(s.t, s.q.data(), m), where,
                                 describe(s)));
}

// Cubic Hermite of q from (q, qd) at both ends (its derivative gives qd), y linear.
void MultibodySystem::interpolate_step(const State& from, const State& to, double th,
                                       State& out) const {
  const double h = to.t - from.t, th2 = th * th, th3 = th2 * th;
  out.t = from.t + th * h;
  out.q = (2 * th3 - 3 * th2 + 1) * from.q + (h * (th3 - 2 * th2 + th)) * from.qd +
          (3 * th2 - 2 * th3) * to.q + (h * (th3 - th2)) * to.qd;
  out.qd = ((6 * th2 - 6 * th) / h) * (from.q - to.q) + (3 * th2 - 4 * th + 1) * from.qd +
           (3 * th2 - 2 * th) * to.qd;
  out.y = (1 - th) * from.y + th * to.y;
}

namespace {

double size_of(const Model::DomainMargin& m) {
  return m.margin;
}
double size_of(const LoopClosure::Singularity& s) {
  return s.pivot;
}

// The smallest margin(th) over [a, b], where it has one minimum, by golden section
// to 1e-12 of the step: (th, its margin).
template <class Margin>
auto smallest_margin_between(const Margin& margin, double a, double b) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  auto mc = margin(c), md = margin(d);
  while (b - a > 1e-12) {
    if (size_of(mc) < size_of(md)) {  // the minimum is in [a, d]
      b = d;
      d = c;
      md = mc;
      c = b - g * (b - a);
      mc = margin(c);
    } else {  // in [c, b]
      a = c;
      c = d;
      mc = md;
      d = a + g * (b - a);
      md = margin(d);
    }
  }
  return size_of(mc) < size_of(md) ? std::pair{c, mc} : std::pair{d, md};
}

// The smallest over [lo, hi] (within [0, 2]) of the parabola through (0, y0), (1, y1), (2, y2).
double parabola_minimum(double y0, double y1, double y2, double lo, double hi) {
  const double c = (y0 - 2 * y1 + y2) / 2, b = y1 - y0 - c;
  const auto p = [&](double x) { return y0 + x * (b + c * x); };
  const double vertex = c > 0 ? std::clamp(-b / (2 * c), lo, hi) : lo;
  return std::min({p(vertex), p(lo), p(hi)});
}

// A measure between samples is located where its parabola comes below either.
constexpr double kLocate = 1e-2;  // near the edge
constexpr double kDeepDip = 0.5;  // or a dip deeper than the samples show: this share of the lowest

// Where to locate the smallest of a measure sampled at th = i/(n - 1) along a step:
// between the samples either side of a sign change (`crossed`, the later one, > 0),
// else about the discrete local minimum (an end: no larger than its inner neighbour)
// whose parabola through it and its neighbours (an end's: its two inner samples)
// comes lowest beside it, where that is below kLocate or kDeepDip of the lowest
// sample: near a tangential minimum the measure is smooth, its dip quadratic.
template <std::size_t n>
std::optional<std::pair<double, double>> dip_to_locate(const std::array<double, n>& size,
                                                       int crossed) {
  static_assert(n >= 3);
  const double spacing = 1.0 / (n - 1);
  if (crossed > 0) return std::pair{(crossed - 1) * spacing, crossed * spacing};
  const int last = static_cast<int>(n) - 1;
  double lowest = std::numeric_limits<double>::infinity();
  int left_of_lowest = 0, right_of_lowest = 0;
  for (int i = 0; i <= last; ++i) {
    const int left = std::max(i - 1, 0), right = std::min(i + 1, last);
    if (size[i] > size[left] || size[i] > size[right]) continue;
    const int first = std::min(left, last - 2);  // the parabola's three samples from here
    const double m = parabola_minimum(size[first], size[first + 1], size[first + 2], left - first,
                                      right - first);
    if (m < lowest) {
      lowest = m;
      left_of_lowest = left;
      right_of_lowest = right;
    }
  }
  const double lowest_sample = *std::min_element(size.begin(), size.end());
  if (!(lowest < kLocate || lowest < kDeepDip * lowest_sample)) return std::nullopt;
  return std::pair{left_of_lowest * spacing, right_of_lowest * spacing};
}

// The smallest measure(th) about a dip (golden section), or the lowest sample
// (at th_lowest) where that is smaller: (th, the measure there).
template <class Measure, class Value>
std::pair<double, Value> closest_point(const Measure& measure, std::pair<double, double> dip,
                                       double th_lowest, const Value& lowest) {
  const auto located = smallest_margin_between(measure, dip.first, dip.second);
  if (size_of(lowest) < size_of(located.second)) return {th_lowest, lowest};
  return located;
}

std::string between_evaluations(const State& from, const State& to) {
  return fmt::format(" (between the evaluations of the step from t = {} to {}, on its interpolant)",
                     from.t, to.t);
}

}  // namespace

Model::DomainMargin MultibodySystem::closest_approach(const State& from, const State& to) {
  const auto margin_at = [&](double th) {
    interpolate_step(from, to, th, edge_state_);
    return model_.smallest_domain_margin(edge_state_.t, edge_state_.q.data(),
                                         domain_arguments_.data());
  };
  // Five samples; an argument that changes sign between two (a pole passed), or a
  // dip between them that comes near the edge, is then located by golden section.
  constexpr int kSamples = 5;  // th = 0, 1/4, .. 1
  std::array<double, kSamples> margin{};
  Model::DomainMargin best;
  double th_best = 0.0;
  int crossed = -1;
  for (int i = 0; i < kSamples; ++i) {
    const double th = i / (kSamples - 1.0);
    const Model::DomainMargin m = margin_at(th);
    if (i > 0 && crossed < 0 &&
        model_.domain_edge_crossed(previous_arguments_.data(), domain_arguments_.data()) >= 0)
      crossed = i;
    std::swap(previous_arguments_, domain_arguments_);
    margin[i] = m.margin;
    if (m.margin < best.margin) {
      best = m;
      th_best = th;
    }
  }
  if (const auto dip = dip_to_locate(margin, crossed))
    std::tie(th_best, best) = closest_point(margin_at, *dip, th_best, best);
  interpolate_step(from, to, th_best, edge_state_);
  return best;
}

// check_step with closed loops: a branch point, or a dependent parameter's domain
// edge, on the step's interpolant (multibody_system.hpp).
void MultibodySystem::check_loop_step(const State& from, const State& to) {
  const Eigen::Index n = model_.nindependent();
  if (from.q.size() != n || to.q.size() != n || from.qd.size() != n || to.qd.size() != n ||
      from.y.size() != to.y.size())
    return;
  const auto singularity_at = [&](double th) {
    interpolate_step(from, to, th, edge_state_);
    return probe_loops_.probe(model_, edge_state_.t, edge_state_.q, probe_x_);
  };
  const bool domains = model_.has_domain_margins();
  const auto margin_at = [&](double th) {
    singularity_at(th);
    return model_.smallest_domain_margin(edge_state_.t, probe_x_.data(), domain_arguments_.data());
  };
  // The loops closed at the samples (the start: the last step's end), in order, from
  // the last solution; a domain argument's sign change between two noted.
  constexpr int kSamples = 3;  // th = 0, 1/2, 1
  int domain_crossed = -1;
  const auto sample_at = [&](int i) {
    const double th = i / (kSamples - 1.0);
    if (!domains) return LoopSample{singularity_at(th), {}};
    const Model::DomainMargin m = margin_at(th);  // the loops closed at th first
    const LoopSample s{probe_loops_.singularity(), m};
    if (i > 0 && domain_crossed < 0 &&
        model_.domain_edge_crossed(previous_arguments_.data(), domain_arguments_.data()) >= 0)
      domain_crossed = i;
    std::swap(previous_arguments_, domain_arguments_);
    return s;
  };
  if (!(from.t == probed_end_t_ && probed_end_q_.size() == n && from.q == probed_end_q_)) {
    probe_loops_ = loops_;
    probed_end_ = sample_at(0);
  }
  std::array<LoopSample, kSamples> sample;
  sample[0] = probed_end_;
  for (int i = 1; i < kSamples; ++i) sample[i] = sample_at(i);
  probed_end_ = sample.back();
  probed_end_t_ = to.t;
  probed_end_q_ = to.q;
  std::array<double, kSamples> pivot{}, margin{};
  int crossed = -1, closest = 0, nearest_edge = 0;
  for (int i = 0; i < kSamples; ++i) {
    pivot[i] = sample[i].branch.pivot;
    margin[i] = sample[i].domain.margin;
    if (pivot[i] < pivot[closest]) closest = i;
    if (margin[i] < margin[nearest_edge]) nearest_edge = i;
    if (i > 0 && crossed < 0 && sample[i].branch.sign != sample[i - 1].branch.sign) crossed = i;
  }
  const auto dip = dip_to_locate(pivot, crossed);
  const auto edge_dip = domains ? dip_to_locate(margin, domain_crossed) : std::nullopt;
  if (!dip && !edge_dip) return;
  const auto th_of = [](int i) { return i / (kSamples - 1.0); };
  if (dip) {
    const double th =
        closest_point(singularity_at, *dip, th_of(closest), sample[closest].branch).first;
    if (singularity_at(th).pivot < LoopClosure::kBranchPoint || crossed > 0) {
      probe_loops_.refuse_branch_point(
          model_, edge_state_.t, probe_x_,
          (crossed > 0 ? ", a branch crossed" : "") + between_evaluations(from, to));
    }
  }
  if (edge_dip) {
    const auto [th, m] =
        closest_point(margin_at, *edge_dip, th_of(nearest_edge), sample[nearest_edge].domain);
    if (m.margin < Model::kDomainMargin) loop_domain_margin_refused(from, to, th, m);
  }
  singularity_at(1.0);  // the next step starts from the end's solution
}

void MultibodySystem::loop_domain_margin_refused(const State& from, const State& to, double th,
                                                 const Model::DomainMargin& m) {
  interpolate_step(from, to, th, edge_state_);
  State x;
  x.t = edge_state_.t;
  x.y = edge_state_.y;
  probe_loops_.close(model_, x.t, edge_state_.q, edge_state_.qd, x.q, x.qd);
  domain_margin_refused(x, m, between_evaluations(from, to).c_str());
}

void MultibodySystem::check_step(const State& from, const State& to) {
  if (!(to.t > from.t)) return;
  if (model_.has_loops()) return check_loop_step(from, to);
  if (!model_.has_domain_margins()) return;
  const Eigen::Index nq = model_.nq();
  if (from.q.size() != nq || to.q.size() != nq || from.qd.size() != nq || to.qd.size() != nq ||
      from.y.size() != to.y.size())
    return;
  const Model::DomainMargin m = closest_approach(from, to);
  if (m.margin < Model::kDomainMargin) {
    domain_margin_refused(edge_state_, m, between_evaluations(from, to).c_str());
  }
}

void MultibodySystem::clear_warnings() {
  warnings_.clear();
  conditioning_warned_ = false;
}

void MultibodySystem::watch_angle_sequences(const State& s, bool ill) {
  if (s.q.size() != model_.nq()) return;
  std::optional<std::string> cause =
      model_.angle_sequence_near_singular(s.q.data(), kAngleSequenceWarning);
  if (!cause && !ill) return;
  if (!cause) {
    const auto name = [this](int j) { return model_.q_names()[j]; };
    cause = fmt::format("the smallest pivot of its factorization is {:.3g} of its diagonal{}",
                        solver_.smallest_pivot_ratio(),
                        M_.rows() == model_.nq() && !model_.has_loops()
                            ? fmt::format(", its weakest direction {}", null_direction(M_, name))
                            : "");
  }
  warnings_.push_back(fmt::format(
      "t = {}: the mass matrix is nearly singular, the accelerations have lost more than half "
      "their digits: {} at {}",
      s.t, *cause, describe(s)));
  conditioning_warned_ = true;
}

void MultibodySystem::explain_non_finite(const State& s, const char* result) const {
  throw_domain_error(s);
  if (source_ == EquationsSource::assembled) check_kinematics(s, KinematicsLevel::velocities, true);
  if (!M_.allFinite()) {
    throw NumericError(fmt::format("t = {}: mass matrix is not finite at {}", s.t, describe(s)));
  }
  for (int j = 0; j < model_.nq(); ++j) {
    if (!std::isfinite(h_(j))) {
      throw NumericError(fmt::format("t = {}: bias force on coordinate '{}' is not finite at {}",
                                     s.t, model_.q_names()[j], describe(s)));
    }
  }
  check_kinematics(s, level_, false);
  throw NumericError(fmt::format("t = {}: {} not finite at {}", s.t, result, describe(s)));
}

void MultibodySystem::evaluate_elements(const State& s) {
  using enum KinematicsLevel;
  if (level_ == positions) model_.positions(s.t, s.q.data(), k_);
  if (level_ == velocities) model_.velocities(s.t, s.q.data(), s.qd.data(), k_);
  if (level_ != none) model_.partial_velocities(s.t, s.q.data(), k_);
  elements_generalized_forces(s);
}

bool MultibodySystem::recursive_accelerations(const State& s, Vector& qdd) {
  check_state(s);
  evaluate_elements(s);
  qdd.resize(h_.size());
  const double* tau = elements_.empty() ? zero_.data() : elements_Q_.data();
  const int failed =
      forward_(s.t, s.q.data(), s.qd.data(), tau, model_.parameters().data(), qdd.data());
  return failed < 0 && all_finite(qdd.data(), qdd.size());
}

void MultibodySystem::accelerations(const State& s, Vector& qdd, Vector& yd) {
  accelerations(s, qdd, yd, false);
}

void MultibodySystem::accelerations(const State& s, Vector& qdd, Vector& yd, bool by_mass_matrix) {
  if (model_.has_loops()) {
    loop_accelerations(s, qdd, yd);
    return;
  }
  const Eigen::Index nq = h_.size();
  if (s.q.size() != nq || s.qd.size() != nq || s.y.size() != extra_initial_.size()) state_error(s);
  check_domain_margin(s);
  mass_factored_ = false;
  bool recursive = false;
  if (forward_ != nullptr && !by_mass_matrix) {  // the way of M tests nothing more
    if (forward_without_elements_ != nullptr) {
      // qdd = M⁻¹·(-h) by the articulated-body algorithm, inline: nothing else to evaluate.
      // The state's values are checked with qdd's after it, as on the way of M below.
      qdd.resize(nq);
      recursive = forward_without_elements_(s.t, s.q.data(), s.qd.data(), zero_.data(),
                                            model_.parameters().data(), qdd.data()) < 0 &&
                  all_finite(s, qdd);
    } else if (source_ == EquationsSource::emitted) {
      // With force elements or kinematics read: the state checked before them.
      recursive = recursive_accelerations(s, qdd);
    }
  }
  // Done: qdd = M⁻¹·(Q - h) by the articulated-body algorithm, state and qdd checked. A
  // failed pivot or a non-finite qdd goes the way of M, whose checks name why.
  if (!recursive) mass_matrix_accelerations(s, qdd);
  watch_conditioning(s, mass_factored_);
  yd.resize(extra_initial_.size());
  if (extra_) extra_(s, k_, yd);
}

// qdd = M⁻¹·(Q - h) by M's factorization, qdd checked.
void MultibodySystem::mass_matrix_accelerations(const State& s, Vector& qdd) {
  const Eigen::Index nq = h_.size();
  if (source_ == EquationsSource::emitted && elements_.empty()) {
    // M qdd = -h. No code of the user's sees the state before its values are checked,
    // with the result's (below): a NaN in the state only propagates through the
    // emitted code, to a refused M or a non-finite qdd, whose reports name the state first.
    if (dynamics_ != nullptr) {
      dynamics_(s.t, s.q.data(), s.qd.data(), model_.parameters().data(), M_.data(), h_.data());
    } else {
      model_.dynamics(s.t, s.q.data(), s.qd.data(), level_, M_.data(), h_.data(), k_);
    }
    if (!solver_.factor(M_)) mass_matrix_refused(s);
    qdd.resize(nq);
    solver_.solve_negated(h_, qdd);
    mass_factored_ = true;
  } else {
    check_state(s);
    accelerations_rhs(s, qdd);
    if (!solver_.factor(M_)) mass_matrix_refused(s);
    solver_.solve_in_place(qdd);
    mass_factored_ = true;
  }
  if (!all_finite(s, qdd)) accelerations_not_finite(s);
}

// (Tᵀ·M_x·T)·qdd = Tᵀ·(Q_x - h_x - M_x·c) (loop_closure.hpp), the tree's M_x
// and Q_x - h_x at the extended state as without loops.
void MultibodySystem::loop_accelerations(const State& s, Vector& qdd, Vector& yd) {
  check_independent(s);
  mass_factored_ = false;
  const State& x = close(s);
  check_domain_margin(x);
  accelerations_rhs(x, rhs_x_);
  const Coupling& coupling = coupling_of(M_, source_ == EquationsSource::emitted);
  // rhs_x -= M_x·c, c = [0; c_p]
  const Eigen::Index n = model_.nindependent(), m = model_.ncon();
  for (Eigen::Index k = 0; k < m; ++k) {
    const double* a = M_.col(n + k).data();
    const double c = loops_.c()(n + k);
    for (int e = coupling.start[static_cast<std::size_t>(k)];
         e < coupling.start[static_cast<std::size_t>(k + 1)]; ++e) {
      const int i = coupling.rows[static_cast<std::size_t>(e)];
      rhs_x_(i) -= a[i] * c;
    }
  }
  Matrix& reduced = derivative_M_;
  reduce(M_, coupling, reduced);
  reduce(rhs_x_, qdd);
  if (!solver_.factor(reduced)) {
    if (!(reduced.allFinite() && qdd.allFinite())) explain_non_finite(x);
    throw NumericError(fmt::format(
        "t = {}: the mass matrix reduced to the independent coordinates of the closed loops is "
        "singular or indefinite (pivot {:.3g} of its diagonal) at {}",
        s.t, solver_.smallest_pivot_ratio(), describe(x)));
  }
  solver_.solve_in_place(qdd);
  mass_factored_ = true;
  if (!all_finite(qdd.data(), qdd.size())) accelerations_not_finite(x);
  watch_conditioning(x, true);
  yd.resize(extra_initial_.size());
  if (extra_) extra_(x, k_, yd);
}

// The right-hand side of M qdd = rhs of a checked state, M in M_: the assembled
// equations, or the emitted ones with force elements.
void MultibodySystem::accelerations_rhs(const State& s, Vector& qdd) {
  if (source_ == EquationsSource::assembled) {
    // M qdd = -f(qdd = 0)
    model_.accelerations(s.t, s.q.data(), s.qd.data(), zero_.data(), k_);
    model_.partial_velocities(s.t, s.q.data(), k_);
    check_kinematics(s, KinematicsLevel::velocities, true);
    apply_elements(s);
    assemble_residual(assembled_residual_, true, true);
    assemble_mass_matrix(M_);
    qdd = -assembled_residual_;
  } else {
    // M qdd = Q - h
    evaluate_equations(s);
    qdd = elements_Q_ - h_;
  }
}

// x closing the loops at s (in the independent coordinates), and xdd_ =
// T·qdd + c, the tree's accelerations that qdd (checked) gives there.
const State& MultibodySystem::close_with_accelerations(const State& s, const Vector& qdd) {
  check_independent(s);
  if (qdd.size() != num_coordinates()) {
    throw ModelError(fmt::format("model '{}': {} accelerations given; expected {}", model_.name(),
                                 qdd.size(), num_coordinates()));
  }
  const State& x = close(s);
  xdd_ = loops_.c();
  xdd_.noalias() += loops_.T() * qdd;
  return x;
}

void MultibodySystem::residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                               Vector& g) {
  if (!model_.has_loops()) {
    tree_residual(s, qdd, yd, f, g);
    return;
  }
  // f = Tᵀ·f_x(xdd = T·qdd + c)
  const State& x = close_with_accelerations(s, qdd);
  tree_residual(x, xdd_, yd, rhs_x_, g);
  reduce(rhs_x_, f);
}

void MultibodySystem::tree_residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                                    Vector& g) {
  check_state(s);
  check_domain_margin(s);
  watch_conditioning(s, false);
  if (qdd.size() != model_.nq()) {
    throw ModelError(fmt::format("model '{}': {} accelerations given; expected {}", model_.name(),
                                 qdd.size(), model_.nq()));
  }
  f.resize(model_.nq());
  if (source_ == EquationsSource::assembled) {
    model_.accelerations(s.t, s.q.data(), s.qd.data(), qdd.data(), k_);
    model_.partial_velocities(s.t, s.q.data(), k_);
    check_kinematics(s, KinematicsLevel::velocities, true);
    apply_elements(s);
    assemble_residual(f, true, true);
  } else if (inverse_ != nullptr) {
    // f = inverse_dynamics(qdd) - Q = M qdd + h - Q
    evaluate_elements(s);
    inverse_(s.t, s.q.data(), s.qd.data(), qdd.data(), model_.parameters().data(), f.data());
    if (!elements_.empty()) f -= elements_Q_;
    if (!all_finite(f.data(), f.size()))
      evaluate_equations(s);  // cold: M and h to name the culprit
  } else {
    // f = M qdd + h - Q
    evaluate_equations(s);
    f.noalias() = M_ * qdd;
    f += h_;
    if (!elements_.empty()) f -= elements_Q_;
  }
  if (!all_finite(f.data(), f.size()))
    explain_non_finite(s, "residual is");  // cold: names the culprit
  g.resize(num_extra_states());
  if (extra_) {
    extra_(s, k_, g);
    g = yd - g;
  }
}

void MultibodySystem::jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C,
                                Matrix& K) {
  if (!exact_jacobians()) {
    jacobians_by_differences(s, qdd, M, C, K);
    return;
  }
  if (model_.has_loops()) {
    exact_loop_jacobians(s, qdd, M, C, K);
    return;
  }
  // f = tau(q, qd, qdd) - Q(q, qd): M = dtau/dqdd, C and K from the emitted
  // derivatives of tau, less those of the force elements' Q.
  exact_damping_stiffness(s, qdd, C, K, &M);
}

template <class Storage>
void MultibodySystem::exact_damping_stiffness(const State& s, const Vector& qdd, Storage& C,
                                              Storage& K, Matrix* M) {
  check_state(s);
  if (qdd.size() != model_.nq()) {
    throw ModelError(fmt::format("model '{}': {} accelerations given; expected {}", model_.name(),
                                 qdd.size(), model_.nq()));
  }
  if (M != nullptr && model_.has_inverse_dynamics_jacobians()) {
    model_.inverse_dynamics_jacobians(s.t, s.q.data(), s.qd.data(), qdd.data(), K, C, *M);
  } else {
    model_.inverse_dynamics_derivatives(s.t, s.q.data(), s.qd.data(), qdd.data(), K, C);
    if (M != nullptr) mass_matrix_emitted(s, *M);
  }
  if (!(all_finite(K.data(), K.size()) && all_finite(C.data(), C.size()) &&
        (M == nullptr || all_finite(M->data(), M->size()))))
    derivatives_not_finite(s);
  if (!elements_.empty()) subtract_load_derivatives(s, C, K);
}

// K = Tᵀ·(K_x·T + C_x·dxd/dq + M_x·dxdd/dq) - Tᵀ·H·T, C = Tᵀ·(C_x·T +
// M_x·dxdd/dqd), M = Tᵀ·M_x·T (loop_closure.hpp), the tree's at the extended
// state and xdd = T·qdd + c.
void MultibodySystem::exact_loop_jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C,
                                           Matrix& K) {
  const State& x = close_with_accelerations(s, qdd);
  jacobian_yd_.setZero(num_extra_states());
  tree_residual(x, xdd_, jacobian_yd_, rhs_x_, jacobian_g_);
  exact_damping_stiffness(x, xdd_, tree_C_, tree_K_, &tree_M_);
  loops_.derivatives(model_, x.t, x.q, x.qd, xdd_, rhs_x_);
  const Matrix& T = loops_.T();
  M.resize(T.cols(), T.cols());
  C.resize(T.cols(), T.cols());
  K.resize(T.cols(), T.cols());
  // K
  tree_KT_.noalias() = tree_K_ * T;
  tree_KT_.noalias() += tree_C_ * loops_.dxd_dq();
  tree_KT_.noalias() += tree_M_ * loops_.dxdd_dq();
  K.noalias() = T.transpose() * tree_KT_;
  K -= loops_.curvature();
  // C
  tree_KT_.noalias() = tree_C_ * T;
  tree_KT_.noalias() += tree_M_ * loops_.dxdd_dqd();
  C.noalias() = T.transpose() * tree_KT_;
  // M
  tree_KT_.noalias() = tree_M_ * T;
  M.noalias() = T.transpose() * tree_KT_;
}

bool MultibodySystem::exact_jacobians() const {
  return use_exact_jacobians_ && source_ == EquationsSource::emitted &&
         model_.has_inverse_dynamics_derivatives() &&
         (!model_.has_loops() || model_.has_constraint_derivatives());
}

std::string MultibodySystem::jacobian_method() const {
  if (model_.has_loops() && !model_.has_constraint_derivatives())
    return "central differences of the residual (closed loops: no exact derivatives)";
  if (!exact_jacobians()) return "central differences of the residual";
  std::string differenced;
  for (const auto& e : elements_) {
    if (!exact_loads(*e)) differenced += (differenced.empty() ? "" : ", ") + e->name();
  }
  if (differenced.empty()) return "exact (emitted derivatives)";
  return "exact (emitted derivatives), but by central differences for " + differenced;
}

bool MultibodySystem::exact_loads(const ForceElement& e) const {
  if (!use_exact_loads_) return false;
  switch (e.load_derivatives()) {
    case LoadDerivatives::exact:
      return true;
    case LoadDerivatives::exact_with_kinematics_derivatives:
      return model_.has_kinematics_derivatives();
    case LoadDerivatives::differenced:
      return false;
  }
  return false;
}

// C -= dQ/dqd, K -= dQ/dq of the force elements' generalized forces Q: exact
// from the elements that give them, the others' part by central differences
// of their Q alone (kinematics and those elements, not M nor h).
template <class Storage>
void MultibodySystem::subtract_load_derivatives(const State& s, Storage& C, Storage& K) {
  const int n = model_.nq();
  Matrix &dQ_dq = load_dq_, &dQ_dqd = load_dqd_;
  dQ_dq.setZero(n, n);
  dQ_dqd.setZero(n, n);
  bool differenced = false, kinematics_derivatives = false;
  for (const auto& e : elements_) {
    differenced = differenced || !exact_loads(*e);
    kinematics_derivatives =
        kinematics_derivatives ||
        (exact_loads(*e) &&
         e->load_derivatives() == LoadDerivatives::exact_with_kinematics_derivatives);
  }
  evaluate_elements_kinematics(s);
  // dk_ is checked only if the loads' derivatives are not finite: most of its entries
  // (every body's, for every pair of coordinates) are read by no element, and those read carry a
  // non-finite value into the derivatives.
  if (kinematics_derivatives) model_.kinematics_derivatives(s.t, s.q.data(), s.qd.data(), dk_);
  for (const auto& e : elements_) {
    if (exact_loads(*e)) e->add_load_derivatives(s, k_, dk_, dQ_dq, dQ_dqd);
  }
  if (differenced) {
    State& p = jacobian_state_;
    p = s;
    Vector &Qp = jacobian_fp_, &Qm = jacobian_fm_;
    // Central differences with a relative step: error O(h^2) against rounding eps/h.
    const auto step = [](double x) { return 1e-6 * std::max(1.0, std::abs(x)); };
    // qd first, from the kinematics at s: positions and partial velocities do not
    // depend on qd, and v_i, w_i are linear in it (v_i = Σ_j dv_i/dqd_j·qd_j + ∂v_i/∂t),
    // so the kinematics at qd ± h·e_j are those at qd shifted along the partial
    // velocities: no evaluation of the model, half the cost of the differences.
    const bool rates = level_ == KinematicsLevel::velocities;
    if (rates) {
      base_v_.assign(k_.v_data(), k_.v_data() + 3 * model_.nbody());
      base_w_.assign(k_.w_data(), k_.w_data() + 3 * model_.nbody());
    }
    for (int j = 0; j < n; ++j) {
      const double h = step(s.qd(j));
      p.qd(j) = s.qd(j) + h;
      if (rates) shift_velocities(j, h);
      differenced_loads(p, Qp);
      p.qd(j) = s.qd(j) - h;
      if (rates) shift_velocities(j, -h);
      differenced_loads(p, Qm);
      p.qd(j) = s.qd(j);
      dQ_dqd.col(j) += (Qp - Qm) / (2.0 * h);
    }
    // q: the kinematics at each shifted state.
    for (int j = 0; j < n; ++j) {
      const double h = step(s.q(j));
      p.q(j) = s.q(j) + h;
      differenced_forces(p, Qp);
      p.q(j) = s.q(j) - h;
      differenced_forces(p, Qm);
      p.q(j) = s.q(j);
      dQ_dq.col(j) += (Qp - Qm) / (2.0 * h);
    }
  }
  if (!(all_finite(dQ_dq.data(), dQ_dq.size()) && all_finite(dQ_dqd.data(), dQ_dqd.size()))) {
    if (kinematics_derivatives && !dk_.all_finite()) derivatives_not_finite(s);
    apply_elements(s);  // names a non-finite load
    throw NumericError(
        fmt::format("t = {}: the derivatives of the force elements' loads are not finite at {}",
                    s.t, describe(s)));
  }
  K -= dQ_dq;
  C -= dQ_dqd;
}

// The kinematics the force elements read, at a checked state.
void MultibodySystem::evaluate_elements_kinematics(const State& s) {
  using enum KinematicsLevel;
  if (level_ == positions) model_.positions(s.t, s.q.data(), k_);
  if (level_ == velocities) model_.velocities(s.t, s.q.data(), s.qd.data(), k_);
  if (level_ != none) {
    model_.partial_velocities(s.t, s.q.data(), k_);
    if (!k_.finite_up_to(level_)) check_kinematics(s, level_, false);
  }
}

// Q of the force elements without derivatives of their own.
void MultibodySystem::differenced_forces(const State& s, Vector& Q) {
  evaluate_elements_kinematics(s);
  differenced_loads(s, Q);
}

void MultibodySystem::shift_velocities(int j, double h) {
  double *v = k_.v_data(), *w = k_.w_data();
  for (int i = 0; i < model_.nbody(); ++i) {
    for (int c = 0; c < 3; ++c) {
      v[3 * i + c] = base_v_[static_cast<std::size_t>(3 * i + c)] + h * k_.dv_dqd(i, j)(c);
      w[3 * i + c] = base_w_[static_cast<std::size_t>(3 * i + c)] + h * k_.dw_dqd(i, j)(c);
    }
  }
}

void MultibodySystem::differenced_loads(const State& s, Vector& Q) {
  loads_.clear();
  for (const auto& e : elements_) {
    if (!exact_loads(*e)) e->apply(s, k_, loads_);
  }
  if (!(loads_.F.allFinite() && loads_.M.allFinite() && loads_.Q.allFinite()))
    apply_elements(s);  // names the culprit
  project_loads(Q);
}

void MultibodySystem::derivatives_not_finite(const State& s) const {
  throw_domain_error(s);
  throw NumericError(fmt::format(
      "t = {}: the derivatives of the equations of motion are not finite at {}", s.t, describe(s)));
}

void MultibodySystem::jacobians_by_differences(const State& s, const Vector& qdd, Matrix& M,
                                               Matrix& C, Matrix& K) {
  const int n = num_coordinates();
  mass_matrix(s, M);
  C.resize(n, n);
  K.resize(n, n);
  // The workspace of the differences, reused: an implicit integrator calls this every few steps.
  State& p = jacobian_state_;
  p = s;
  Vector& yd = jacobian_yd_;
  yd.setZero(num_extra_states());
  Vector &fp = jacobian_fp_, &fm = jacobian_fm_, &g = jacobian_g_;
  // Central differences with a relative step: error O(h^2) against rounding eps/h.
  for (int j = 0; j < n; ++j) {
    const double hq = 1e-6 * std::max(1.0, std::abs(s.q(j)));
    p.q(j) = s.q(j) + hq;
    residual(p, qdd, yd, fp, g);
    p.q(j) = s.q(j) - hq;
    residual(p, qdd, yd, fm, g);
    p.q(j) = s.q(j);
    K.col(j) = (fp - fm) / (2.0 * hq);
    const double hv = 1e-6 * std::max(1.0, std::abs(s.qd(j)));
    p.qd(j) = s.qd(j) + hv;
    residual(p, qdd, yd, fp, g);
    p.qd(j) = s.qd(j) - hv;
    residual(p, qdd, yd, fm, g);
    p.qd(j) = s.qd(j);
    C.col(j) = (fp - fm) / (2.0 * hv);
  }
}

bool MultibodySystem::exact_acceleration_derivatives(const State& s, const Vector& qdd,
                                                     Matrix& dqdd_dq, Matrix& dqdd_dqd) {
  if (!exact_jacobians() || num_extra_states() > 0) return false;
  acceleration_derivatives(s, qdd, dqdd_dq, dqdd_dqd);
  return true;
}

void MultibodySystem::acceleration_derivatives(const State& s, const Vector& qdd, Matrix& dqdd_dq,
                                               Matrix& dqdd_dqd, const Matrix* factored) {
  // M·dqdd = -(K·dq + C·dqd) + dtau. Exact on a tree, K and C are solved as emitted (row-major).
  const bool as_emitted = exact_jacobians() && !model_.has_loops();
  const bool reuse = as_emitted && factored != nullptr;
  if (as_emitted) {
    exact_damping_stiffness(s, qdd, damping_rows_, stiffness_rows_,
                            reuse ? nullptr : &derivative_M_);
  } else {
    jacobians(s, qdd, derivative_M_, dqdd_dqd, dqdd_dq);
  }
  const Matrix& M = reuse ? *factored : derivative_M_;
  // All columns of each in one solve; a tree's M without its zeros (TreeSolver).
  tree_factored_ = tree_solver_.factor(M);
  if (!tree_factored_ && !reuse && !solver_.factor(M)) {
    M_ = M;
    mass_matrix_refused(s);
  }
  const auto solve = [&](auto& solver) {
    if (as_emitted) {
      solver.solve_negated(stiffness_rows_, dqdd_dq);
      solver.solve_negated(damping_rows_, dqdd_dqd);
    } else {
      solver.solve_negated_in_place(dqdd_dq);
      solver.solve_negated_in_place(dqdd_dqd);
    }
  };
  if (tree_factored_) {
    solve(tree_solver_);
  } else {
    solve(solver_);
  }
}

void MultibodySystem::dynamics_derivatives(const State& s, DynamicsDerivatives& out,
                                           bool with_input_matrix, const Vector& tau) {
  // The exact derivatives' solves need M factored: qdd by the way of M too, one
  // M and one factorization (the recursive way would evaluate M once more), on
  // a few coordinates. On many, M's conditioning grows and the two ways' qdd part
  // by more than the derivatives' rounding (chain_64: 1e-10 of ∂qdd/∂q,
  // bench/results/derivatives.md): there qdd stays the recursive way's.
  constexpr int kQddByMassMatrixUpTo = 20;
  accelerations(s, out.qdd, jacobian_yd_,
                exact_jacobians() && num_coordinates() <= kQddByMassMatrixUpTo);
  // Where accelerations() took the way of M, M at s is factored already (the
  // loops' reduced one in derivative_M_).
  const Matrix* factored = nullptr;
  if (mass_factored_) factored = model_.has_loops() ? &derivative_M_ : &M_;
  if (tau.size() > 0) {
    // qdd += M⁻¹·tau: the residual M·qdd + h - Q - tau vanishes there.
    if (tau.size() != num_coordinates() || !all_finite(tau.data(), tau.size())) {
      throw ModelError(
          fmt::format("model '{}': generalized forces tau must be {} finite values ({} given)",
                      model_.name(), num_coordinates(), tau.size()));
    }
    if (factored == nullptr) {
      mass_matrix(s, derivative_M_);
      if (!solver_.factor(derivative_M_)) {
        M_ = derivative_M_;
        mass_matrix_refused(s);
      }
      factored = &derivative_M_;
    }
    Vector& added = jacobian_fp_;
    added = tau;
    solver_.solve_in_place(added);
    out.qdd += added;
  }
  acceleration_derivatives(s, out.qdd, out.dqdd_dq, out.dqdd_dqd, factored);
  if (!with_input_matrix) {
    out.dqdd_dtau.resize(0, 0);
    return;
  }
  // M is factored (acceleration_derivatives): M⁻¹ = M⁻¹·1.
  out.dqdd_dtau.setIdentity(num_coordinates(), num_coordinates());
  if (tree_factored_) {
    tree_solver_.solve_in_place(out.dqdd_dtau);
  } else {
    solver_.solve_in_place(out.dqdd_dtau);
  }
}

Energies MultibodySystem::energies(const State& s) {
  if (reduces(s)) return energies(State(extended(s)));
  evaluate_kinematics(s);
  Energies e;
  e.kinetic = kinetic_energy(model_, k_);
  e.gravitational = gravitational_energy(model_, k_);
  for (const auto& el : elements_) e.elastic += el->potential_energy(s, k_);
  return e;
}

Momentum MultibodySystem::momentum(const State& s) {
  if (reduces(s)) return momentum(extended(s));
  evaluate_kinematics(s);
  return runtime::momentum(model_, k_);
}

void MultibodySystem::joint_reactions(const State& s, Matrix& reaction) {
  Vector qdd, yd(num_extra_states());
  accelerations(s, qdd, yd);
  joint_reactions(s, qdd, reaction);
}

void MultibodySystem::joint_reactions(const State& s, const Vector& qdd, Matrix& reaction) {
  if (!model_.has_joint_reactions()) {
    throw ModelError(fmt::format(
        "model '{}' (variant '{}') was emitted without joint_reactions (generator --reactions, "
        "REACTIONS in symdyn_add_model)",
        model_.name(), model_.variant()));
  }
  if (reduces(s)) {
    loop_joint_reactions(s, qdd, reaction);
    return;
  }
  if (qdd.size() != model_.nq()) {
    throw ModelError(fmt::format("joint reactions: qdd has {} entries, model '{}' {} coordinates",
                                 qdd.size(), model_.name(), model_.nq()));
  }
  evaluate_kinematics(s);
  apply_elements(s);
  reaction.resize(6, model_.nbody());
  model_.joint_reactions(s.t, s.q.data(), s.qd.data(), qdd.data(), loads_.F.data(), loads_.M.data(),
                         reaction.data());
  check_reactions(s, reaction);
}

void MultibodySystem::check_reactions(const State& s, const Matrix& reaction) const {
  for (int i = 0; i < model_.nbody(); ++i) {
    if (!reaction.col(i).allFinite()) {
      throw NumericError(fmt::format("t = {}: the joint reaction of body '{}' is not finite at {}",
                                     s.t, model_.body_names()[i], describe(s)));
    }
  }
}

// The tree's joints at x = (q, p) with the closures' forces as applied loads:
// each body's Newton-Euler balance then holds with every force it receives.
void MultibodySystem::loop_joint_reactions(const State& s, const Vector& qdd, Matrix& reaction) {
  for (int k = 0; k < model_.ncon(); ++k) {
    const int loop = model_.constraint_loop(k);
    if (model_.loop_body_a(loop) < 0 || !model_.has_closure_points()) {
      throw ModelError(fmt::format(
          "joint reactions of model '{}': loop '{}' is given by its equations (constraint), "
          "whose forces act on no known body; close it with close_loop for its joints' reactions",
          model_.name(), model_.loop_names()[static_cast<std::size_t>(loop)]));
    }
  }
  Vector lambda;
  loop_multipliers(s, qdd, lambda);  // closed_ and xdd_ at s
  const State& x = closed_;
  evaluate_kinematics(x);
  apply_elements(x);
  add_closure_loads(x, lambda);
  reaction.resize(6, model_.nbody());
  model_.joint_reactions(x.t, x.q.data(), x.qd.data(), xdd_.data(), loads_.F.data(),
                         loads_.M.data(), reaction.data());
  check_reactions(x, reaction);
}

// The closure of equation k pulls body a with λ_k·e_axis at the point P and
// body b with the opposite force: at each G a force and the moment (P - x)×F.
void MultibodySystem::add_closure_loads(const State& x, const Vector& lambda) {
  Matrix points(3, model_.ncon());  // column k: row k of the emitted (ncon x 3)
  model_.closure_points(x.t, x.q.data(), points.data());
  for (int k = 0; k < model_.ncon(); ++k) {
    const int loop = model_.constraint_loop(k);
    Vec3 force = Vec3::Zero();
    force(model_.constraint_axis(k)) = lambda(k);
    const Vec3 point = points.col(k);
    const int a = model_.loop_body_a(loop), b = model_.loop_body_b(loop);
    loads_.F.col(a) += force;
    loads_.M.col(a) += (point - k_.x(a)).cross(force);
    loads_.F.col(b) -= force;
    loads_.M.col(b) -= (point - k_.x(b)).cross(force);
  }
}

void MultibodySystem::loop_multipliers(const State& s, const Vector& qdd, Vector& lambda) {
  if (!model_.has_loops())
    throw ModelError(fmt::format("model '{}' has no closed loops", model_.name()));
  const State& x = close_with_accelerations(s, qdd);
  Vector yd = Vector::Zero(num_extra_states()), g;
  tree_residual(x, xdd_, yd, rhs_x_, g);
  loops_.multipliers(rhs_x_.tail(model_.ncon()), lambda);
  if (!lambda.allFinite())
    throw NumericError(
        fmt::format("t = {}: the loops' multipliers are not finite at {}", s.t, describe(x)));
}

void MultibodySystem::loop_reactions(const State& s, Vector& reaction) {
  Vector qdd, yd(num_extra_states());
  accelerations(s, qdd, yd);
  loop_reactions(s, qdd, reaction);
}

void MultibodySystem::loop_reactions(const State& s, const Vector& qdd, Vector& reaction) {
  loop_multipliers(s, qdd, reaction);
  for (int k = 0; k < model_.ncon(); ++k) {
    if (model_.constraint_axis(k) >= 0) reaction(k) = -reaction(k);
  }
}

SourceComparison compare_sources(MultibodySystem& system, const State& s) {
  if (!system.model().has_equations_of_motion()) {
    throw ModelError(fmt::format("model '{}': no emitted equations of motion to compare with",
                                 system.model().name()));
  }
  Matrix Ma, Me;
  Vector ha, he;
  system.mass_matrix_assembled(s, Ma);
  system.mass_matrix_emitted(s, Me);
  system.bias_forces_assembled(s, ha);
  system.bias_forces_emitted(s, he);
  SourceComparison c;
  c.mass_matrix = (Ma - Me).cwiseAbs().maxCoeff();
  c.bias_forces = (ha - he).cwiseAbs().maxCoeff();
  return c;
}

}  // namespace symdyn::runtime
