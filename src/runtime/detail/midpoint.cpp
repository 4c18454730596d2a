#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include <symdyn/runtime/detail/midpoint.hpp>
#include <symdyn/runtime/detail/stepping_integrator.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace symdyn::runtime {

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

class Midpoint final : public detail::SteppingIntegrator {
 public:
  using SteppingIntegrator::SteppingIntegrator;
  std::string_view name() const override { return "midpoint"; }

 private:
  bool fixed_step_only() const override { return true; }
  double first_step(double) override { return options_.initial_step; }
  void start(const State& initial) override;
  int order() const override { return 2; }
  bool symmetric() const override { return true; }
  detail::StepOutcome attempt(double h, bool fixed) override;
  std::string map(double h, const Vector& z, Vector& Gz);
  double change(const Vector& dz, const Vector& z) const;
  std::string factor_newton_matrix(double h, const Vector& z, const Vector& Gz);
  std::string factor_exact_newton_matrix(double h);
  void mass_product_derivative(const State& at, const Vector& x, Matrix& M, Matrix& B);

  void mass_matrix(double t, const Vector& q, const Vector& y, Matrix& M);
  void mass_times(double t, const Vector& q, const Vector& y, const Vector& x, Vector& Mx);
  void momentum_rate(double t, const Vector& q, const Vector& v, const Vector& y, const Vector& qdd,
                     const Matrix& M, Vector& pdot);
  std::string end_of_step(double t1);

  int n_ = 0;
  int m_ = 0;
  Vector q_scale_;            // (n) options.q_scale, or ones
  Vector p_;                  // (n) momentum at current_
  Vector pdot_;               // (n) the last step's midpoint dp/dt: the next step's guess
  Vector q1_, p1_, y1_;       // (n), (n), (m) the step being solved
  Vector qm_, pm_, vm_, ym_;  // midpoint values
  Vector qdd_m_, yd_m_;       // accelerations at the midpoint
  Matrix M_;                  // (n x n)
  Eigen::PartialPivLU<Matrix> lu_;
  Eigen::PartialPivLU<Matrix> newton_lu_;  // of I - dG/dz, (2n+m x 2n+m)
  State probe_;                            // scratch state for the residuals
  Vector rest_residual_;                   // (n) f at qd = 0, qdd = 0 (gravity and the like)
  Vector probe_residual_;                  // (n) f at qd = 0, qdd = λ·x
  Vector g_, zero_n_, zero_m_, Mv_plus_, Mv_minus_;
  // Workspaces sized once, so that a step allocates nothing.
  Vector amplified_, unit_, shifted_q_;  // (n) λ·x, λ·e_j, q ± d·v
  Vector qdd1_, yd1_;                    // (n), (m) at the end of the step being solved
  Vector z_, Gz_, dz_, newton_rhs_;      // (2n + m) the iteration's unknown, map, update
  Vector z_probe_, Gz_probe_;            // (2n + m) the difference Jacobian's probes
  Matrix newton_matrix_;                 // (2n + m x 2n + m) I - dG/dz
  // Whether the Newton matrix comes from the system's exact Jacobians (m = 0), and their
  // workspaces (n x n).
  bool exact_ = false;
  Matrix Mj_, C_, K_, B_, M_plus_, B_plus_, M_minus_, B_minus_, M_inverse_;
  Matrix dv_dq_, dp_dq_, dp_dv_;
  SpdSolver exact_mass_;  // of M at the midpoint, for M⁻¹
};

// The power of two nearest to 1e6·max(1, |f0|)/|x|, f0 the residual at rest:
// M·x = (f(λ·x) - f0)/λ with λ·x far larger than f0 loses only eps·|M·x| to rounding,
// not eps·|f0| (gravity, say); a power of two scales exactly.
double amplification(const Vector& rest_residual, double x_size) {
  const double target = 1e6 * std::max(1.0, rest_residual.lpNorm<Eigen::Infinity>()) / x_size;
  return std::exp2(std::round(std::log2(target)));
}

// M·x = (f(t, q, 0, λ·x, y) - f(t, q, 0, 0, y))/λ.
void Midpoint::mass_times(double t, const Vector& q, const Vector& y, const Vector& x, Vector& Mx) {
  probe_.t = t;
  probe_.q = q;
  probe_.qd = zero_n_;
  probe_.y = y;
  residual(probe_, zero_n_, zero_m_, rest_residual_, g_);
  const double size = x.lpNorm<Eigen::Infinity>();
  if (size == 0.0) {
    Mx = zero_n_;
    return;
  }
  const double lambda = amplification(rest_residual_, size);
  amplified_ = lambda * x;
  residual(probe_, amplified_, zero_m_, probe_residual_, g_);
  Mx = (probe_residual_ - rest_residual_) / lambda;
}

// M column by column: n + 1 residuals, amplified as in mass_times.
void Midpoint::mass_matrix(double t, const Vector& q, const Vector& y, Matrix& M) {
  probe_.t = t;
  probe_.q = q;
  probe_.qd = zero_n_;
  probe_.y = y;
  residual(probe_, zero_n_, zero_m_, rest_residual_, g_);
  const double lambda = amplification(rest_residual_, 1.0);
  M.resize(n_, n_);
  unit_.setZero(n_);
  for (int j = 0; j < n_; ++j) {
    unit_[j] = lambda;
    residual(probe_, unit_, zero_m_, probe_residual_, g_);
    M.col(j) = (probe_residual_ - rest_residual_) / lambda;
    unit_[j] = 0.0;
  }
}

// dp/dt = M·qdd + Ṁ·v, Ṁ·v = (M(q + d·v) - M(q - d·v))·v / (2d): a central
// difference with d·|v / q_scale| = cbrt(eps) (truncation and rounding balanced). The
// scale of q, not |q|: M varies with an angle over a radian however far it has wound.
void Midpoint::momentum_rate(double t, const Vector& q, const Vector& v, const Vector& y,
                             const Vector& qdd, const Matrix& M, Vector& pdot) {
  pdot.noalias() = M * qdd;
  const double speed = v.cwiseQuotient(q_scale_).lpNorm<Eigen::Infinity>();
  if (speed == 0.0) return;
  const double d = std::cbrt(eps) / speed;
  shifted_q_ = q + d * v;
  mass_times(t, shifted_q_, y, v, Mv_plus_);
  shifted_q_ = q - d * v;
  mass_times(t, shifted_q_, y, v, Mv_minus_);
  pdot += (Mv_plus_ - Mv_minus_) / (2.0 * d);
}

void Midpoint::start(const State& initial) {
  n_ = system_->num_coordinates();
  m_ = system_->num_extra_states();
  zero_n_ = Vector::Zero(n_);
  zero_m_ = Vector::Zero(m_);
  q_scale_ = Vector::Ones(n_);
  for (std::size_t i = 0; i < options_.q_scale.size(); ++i) {
    q_scale_[static_cast<Eigen::Index>(i)] = options_.q_scale[i];
  }
  current_ = initial;
  mass_matrix(initial.t, initial.q, initial.y, M_);
  p_.resize(n_);
  p_.noalias() = M_ * initial.qd;
  qdd_.resize(n_);
  yd_.resize(m_);
  qdd1_.resize(n_);
  yd1_.resize(m_);
  qdd_m_.resize(n_);
  yd_m_.resize(m_);
  accelerations(current_, qdd_, yd_);
  const std::string bad = detail::non_finite_value(*system_, current_, qdd_, yd_);
  if (!bad.empty()) throw NumericError(detail::at_time(initial.t, bad));
  momentum_rate(initial.t, initial.q, initial.qd, initial.y, qdd_, M_, pdot_);
  Matrix dqdd_dq, dqdd_dqd;
  exact_ = m_ == 0 && system_->exact_acceleration_derivatives(current_, qdd_, dqdd_dq, dqdd_dqd);
  if (exact_) exact_mass_ = SpdSolver(n_);
}

// qd1 = M(q1)⁻¹·p1 and (qdd1, yd1) at the step end; "" or what went wrong.
std::string Midpoint::end_of_step(double t1) {
  mass_matrix(t1, q1_, y1_, M_);
  lu_.compute(M_);
  probe_.t = t1;
  probe_.q = q1_;
  probe_.qd = lu_.solve(p1_);
  probe_.y = y1_;
  accelerations(probe_, qdd1_, yd1_);
  std::string bad = detail::non_finite_value(*system_, probe_, qdd1_, yd1_);
  if (!bad.empty()) return detail::at_time(t1, bad);
  current_ = probe_;
  qdd_ = qdd1_;
  yd_ = yd1_;
  p_ = p1_;
  return {};
}

// G(z) for z = (q1, p1, y1) (2n + m): (q0 + h·vm, p0 + h·ṗm, y0 + h·ydm) at the
// midpoint of z and the step start. "" or what went wrong.
std::string Midpoint::map(double h, const Vector& z, Vector& Gz) {
  const double tm = current_.t + 0.5 * h;
  qm_ = 0.5 * (current_.q + z.head(n_));
  pm_ = 0.5 * (p_ + z.segment(n_, n_));
  ym_ = 0.5 * (current_.y + z.tail(m_));
  mass_matrix(tm, qm_, ym_, M_);
  lu_.compute(M_);
  vm_ = lu_.solve(pm_);
  probe_.t = tm;
  probe_.q = qm_;
  probe_.qd = vm_;
  probe_.y = ym_;
  try {
    accelerations(probe_, qdd_m_, yd_m_);
  } catch (const NumericError& e) {
    return detail::at_time(tm, e.what());
  }
  const std::string bad = detail::non_finite_value(*system_, probe_, qdd_m_, yd_m_);
  if (!bad.empty()) return detail::at_time(tm, bad);
  momentum_rate(tm, qm_, vm_, ym_, qdd_m_, M_, pdot_);
  Gz.resize(z.size());
  Gz << current_.q + h * vm_, p_ + h * pdot_, current_.y + h * yd_m_;
  return {};
}

// Largest |dz_i| relative to q_scale for q (never |q|, which winds up) and to the
// size of p and y.
double Midpoint::change(const Vector& dz, const Vector& z) const {
  double c = 0.0;
  for (Eigen::Index i = 0; i < dz.size(); ++i) {
    const double size = i < n_ ? q_scale_[i] : std::max(1.0, std::abs(z[i]));
    c = std::max(c, std::abs(dz[i]) / size);
  }
  return c;
}

// (I - dG/dz) by forward differences at z, factored for Newton's updates.
std::string Midpoint::factor_newton_matrix(double h, const Vector& z, const Vector& Gz) {
  const Eigen::Index size = z.size();
  newton_matrix_.setIdentity(size, size);
  z_probe_ = z;
  for (Eigen::Index j = 0; j < size; ++j) {
    const double scale = j < n_ ? q_scale_[j] : std::max(1.0, std::abs(z[j]));
    const double d = std::sqrt(eps) * std::max(scale, std::abs(z[j]));
    z_probe_[j] = z[j] + d;
    const std::string bad = map(h, z_probe_, Gz_probe_);
    if (!bad.empty()) return bad;
    newton_matrix_.col(j) -= (Gz_probe_ - Gz) / (z_probe_[j] - z[j]);
    z_probe_[j] = z[j];
  }
  newton_lu_.compute(newton_matrix_);
  return {};
}

// ∂(M(q)·x)/∂q = K(q, v, x) - K(q, v, 0) (f is linear in qdd, with coefficient M(q)),
// and M, at the state `at`.
void Midpoint::mass_product_derivative(const State& at, const Vector& x, Matrix& M, Matrix& B) {
  system_->jacobians(at, zero_n_, M, C_, K_);
  system_->jacobians(at, x, M, C_, B);
  B -= K_;
}

// I - dG/dz from the system's exact Jacobians at the midpoint of the last map (qm_, vm_;
// m = 0). With ṗ(q, v) = -f(q, v, 0) + Ṁ(q, v)·v, B = ∂(M·vm)/∂q, and Ṁ and ∂B/∂q·vm by
// central differences along vm as in momentum_rate (whose Ṁ·v they differentiate):
//   ∂vm/∂q1 = -M⁻¹·B/2,  ∂vm/∂p1 = M⁻¹/2,
//   ∂ṗ/∂q = -K + ∂B/∂q·vm,  ∂ṗ/∂v = -C + Ṁ + B  (K, C at qdd = 0),
//   ∂ṗm/∂q1 = ∂ṗ/∂q/2 + ∂ṗ/∂v·∂vm/∂q1,  ∂ṗm/∂p1 = ∂ṗ/∂v·M⁻¹/2.
std::string Midpoint::factor_exact_newton_matrix(double h) {
  probe_.t = current_.t + 0.5 * h;
  probe_.qd = vm_;
  probe_.y = ym_;
  const double speed = vm_.cwiseQuotient(q_scale_).lpNorm<Eigen::Infinity>();
  const double d = speed > 0.0 ? std::cbrt(eps) / speed : 0.0;
  try {
    M_plus_.setZero(n_, n_);
    B_plus_.setZero(n_, n_);
    M_minus_.setZero(n_, n_);
    B_minus_.setZero(n_, n_);
    if (speed > 0.0) {
      probe_.q = qm_ + d * vm_;
      mass_product_derivative(probe_, vm_, M_plus_, B_plus_);
      probe_.q = qm_ - d * vm_;
      mass_product_derivative(probe_, vm_, M_minus_, B_minus_);
    }
    probe_.q = qm_;
    mass_product_derivative(probe_, vm_, Mj_, B_);  // and K, C at qdd = 0 (C_ and K_)
  } catch (const NumericError& e) {
    return detail::at_time(probe_.t, e.what());
  }
  const double over_2d = speed > 0.0 ? 0.5 / d : 0.0;
  if (!exact_mass_.factor(Mj_)) {
    return detail::at_time(probe_.t, "the mass matrix at the midpoint is not positive definite");
  }
  M_inverse_.setIdentity(n_, n_);
  exact_mass_.solve_in_place(M_inverse_);
  dv_dq_.noalias() = -0.5 * M_inverse_ * B_;
  dp_dq_ = -K_ + over_2d * (B_plus_ - B_minus_);
  dp_dv_ = -C_ + over_2d * (M_plus_ - M_minus_) + B_;
  newton_matrix_.setIdentity(2 * n_, 2 * n_);
  newton_matrix_.topLeftCorner(n_, n_) -= h * dv_dq_;
  newton_matrix_.topRightCorner(n_, n_) -= (0.5 * h) * M_inverse_;
  newton_matrix_.bottomLeftCorner(n_, n_).noalias() -= (0.5 * h) * dp_dq_;
  newton_matrix_.bottomLeftCorner(n_, n_).noalias() -= h * dp_dv_ * dv_dq_;
  newton_matrix_.bottomRightCorner(n_, n_).noalias() -= (0.5 * h) * dp_dv_ * M_inverse_;
  if (!newton_matrix_.allFinite()) {
    return detail::at_time(probe_.t, "the midpoint's Newton matrix is not finite");
  }
  newton_lu_.compute(newton_matrix_);
  return {};
}

// Fixed-point iteration z <- G(z), which contracts by about h·|dG/dz|/2; when it
// contracts slowly (fast motion, large step), Newton on z - G(z) = 0 takes over, its
// matrix from the exact Jacobians (exact_) or by differences of the map.
detail::StepOutcome Midpoint::attempt(double h, bool) {
  const double t1 = current_.t + h;
  // Guess: q advanced by Taylor, p and y by the last rates.
  Vector& z = z_;
  Vector& Gz = Gz_;
  Vector& dz = dz_;
  z.resize(2 * n_ + m_);
  z << current_.q + h * current_.qd + (0.5 * h * h) * qdd_, p_ + h * pdot_, current_.y + h * yd_;
  bool newton = false;
  double previous_change = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= options_.max_newton_iterations; ++k) {
    std::string bad = map(h, z, Gz);
    if (!bad.empty()) return {false, h, bad};
    if (newton) {
      newton_rhs_ = Gz - z;
      dz = newton_lu_.solve(newton_rhs_);
    } else {
      dz = Gz - z;
    }
    z += dz;
    ++stats_.newton_iterations;
    const double c = change(dz, z);
    if (!std::isfinite(c)) break;
    // Converged at rounding level, or Newton stalled at the level of the rounding
    // noise of M and Ṁ·v from residual differences (the change no longer halves).
    if (c <= 4.0 * eps || (newton && c < 1e-7 && c > 0.5 * previous_change)) {
      q1_ = z.head(n_);
      p1_ = z.segment(n_, n_);
      y1_ = z.tail(m_);
      const std::string failure = end_of_step(t1);
      return {failure.empty(), h, failure};
    }
    if (!newton && k >= 3 && c > 0.25 * previous_change) {
      bad = map(h, z, Gz);
      if (bad.empty())
        bad = exact_ ? factor_exact_newton_matrix(h) : factor_newton_matrix(h, z, Gz);
      if (!bad.empty()) return {false, h, bad};
      ++stats_.jacobian_evaluations;
      newton = true;
    }
    previous_change = c;
  }
  return {false, h,
          detail::at_time(t1, fmt::format("midpoint iteration did not converge in {} iterations",
                                          options_.max_newton_iterations))};
}

}  // namespace

std::unique_ptr<Integrator> make_midpoint(IntegratorOptions options) {
  return std::make_unique<Midpoint>(std::move(options));
}

}  // namespace symdyn::runtime
