#include "runtime/midpoint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>
#include <fmt/format.h>

#include "runtime/errors.hpp"
#include "runtime/stepping_integrator.hpp"

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
  detail::StepOutcome attempt(double h, bool fixed) override;

  void mass_matrix(double t, const Vector& q, const Vector& y, Matrix& M);
  void mass_times(double t, const Vector& q, const Vector& y, const Vector& x, Vector& Mx);
  void momentum_rate(double t, const Vector& q, const Vector& v, const Vector& y, const Vector& qdd,
                     const Matrix& M, Vector& pdot);
  std::string end_of_step(double t1);

  int n_ = 0;
  int m_ = 0;
  Vector q_scale_;               // (n) options.q_scale, or ones
  Vector p_;                     // (n) momentum at current_
  Vector pdot_;                  // (n) the last step's midpoint dp/dt: the next step's guess
  Vector q1_, p1_, y1_;          // (n), (n), (m) the step being solved
  Vector qm_, pm_, vm_, ym_;     // midpoint values
  Vector qdd_m_, yd_m_;          // accelerations at the midpoint
  Matrix M_;                     // (n x n)
  Eigen::PartialPivLU<Matrix> lu_;
  State probe_;                  // scratch state for the residuals
  Vector f0_, f1_, g_, zero_n_, zero_m_, Mv_plus_, Mv_minus_;
};

// The power of two nearest to 1e6·max(1, |f0|)/|x|: M·x = (f(λ·x) - f0)/λ with λ·x
// far larger than f0 loses only eps·|M·x| to rounding, not eps·|f0| (gravity, say);
// a power of two scales exactly.
double amplification(const Vector& f0, double x_size) {
  const double target = 1e6 * std::max(1.0, f0.lpNorm<Eigen::Infinity>()) / x_size;
  return std::exp2(std::round(std::log2(target)));
}

// M·x = (f(t, q, 0, λ·x, y) - f(t, q, 0, 0, y))/λ.
void Midpoint::mass_times(double t, const Vector& q, const Vector& y, const Vector& x, Vector& Mx) {
  probe_.t = t;
  probe_.q = q;
  probe_.qd = zero_n_;
  probe_.y = y;
  residual(probe_, zero_n_, zero_m_, f0_, g_);
  const double size = x.lpNorm<Eigen::Infinity>();
  if (size == 0.0) {
    Mx = zero_n_;
    return;
  }
  const double lambda = amplification(f0_, size);
  residual(probe_, lambda * x, zero_m_, f1_, g_);
  Mx = (f1_ - f0_) / lambda;
}

// M column by column: n + 1 residuals, amplified as in mass_times.
void Midpoint::mass_matrix(double t, const Vector& q, const Vector& y, Matrix& M) {
  probe_.t = t;
  probe_.q = q;
  probe_.qd = zero_n_;
  probe_.y = y;
  residual(probe_, zero_n_, zero_m_, f0_, g_);
  const double lambda = amplification(f0_, 1.0);
  M.resize(n_, n_);
  Vector e = zero_n_;
  for (int j = 0; j < n_; ++j) {
    e[j] = lambda;
    residual(probe_, e, zero_m_, f1_, g_);
    M.col(j) = (f1_ - f0_) / lambda;
    e[j] = 0.0;
  }
}

// dp/dt = M·qdd + Ṁ·v, Ṁ·v = (M(q + d·v) - M(q - d·v))·v / (2d): a central
// difference with d·|v / q_scale| = cbrt(eps) (truncation and rounding balanced). The
// scale of q, not |q|: M varies with an angle over a radian however far it has wound.
void Midpoint::momentum_rate(double t, const Vector& q, const Vector& v, const Vector& y,
                             const Vector& qdd, const Matrix& M, Vector& pdot) {
  pdot = M * qdd;
  const double speed = v.cwiseQuotient(q_scale_).lpNorm<Eigen::Infinity>();
  if (speed == 0.0) return;
  const double d = std::cbrt(eps) / speed;
  mass_times(t, q + d * v, y, v, Mv_plus_);
  mass_times(t, q - d * v, y, v, Mv_minus_);
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
  p_ = M_ * initial.qd;
  qdd_.resize(n_);
  yd_.resize(m_);
  accelerations(current_, qdd_, yd_);
  const std::string bad = detail::non_finite_value(*system_, current_, qdd_, yd_);
  if (!bad.empty()) throw NumericError(detail::at_time(initial.t, bad));
  momentum_rate(initial.t, initial.q, initial.qd, initial.y, qdd_, M_, pdot_);
}

// qd1 = M(q1)⁻¹·p1 and (qdd1, yd1) at the step end; "" or what went wrong.
std::string Midpoint::end_of_step(double t1) {
  mass_matrix(t1, q1_, y1_, M_);
  lu_.compute(M_);
  probe_.t = t1;
  probe_.q = q1_;
  probe_.qd = lu_.solve(p1_);
  probe_.y = y1_;
  Vector qdd(n_), yd(m_);
  accelerations(probe_, qdd, yd);
  std::string bad = detail::non_finite_value(*system_, probe_, qdd, yd);
  if (!bad.empty()) return detail::at_time(t1, bad);
  current_ = probe_;
  qdd_ = qdd;
  yd_ = yd;
  p_ = p1_;
  return {};
}

detail::StepOutcome Midpoint::attempt(double h, bool) {
  const double t0 = current_.t;
  const double tm = t0 + 0.5 * h;
  // Guess: q advanced by Taylor, p and y by the last rates.
  q1_ = current_.q + h * current_.qd + (0.5 * h * h) * qdd_;
  p1_ = p_ + h * pdot_;
  y1_ = current_.y + h * yd_;
  double previous_change = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= options_.max_newton_iterations; ++k) {
    qm_ = 0.5 * (current_.q + q1_);
    pm_ = 0.5 * (p_ + p1_);
    ym_ = 0.5 * (current_.y + y1_);
    mass_matrix(tm, qm_, ym_, M_);
    lu_.compute(M_);
    vm_ = lu_.solve(pm_);
    probe_.t = tm;
    probe_.q = qm_;
    probe_.qd = vm_;
    probe_.y = ym_;
    qdd_m_.resize(n_);
    yd_m_.resize(m_);
    try {
      accelerations(probe_, qdd_m_, yd_m_);
    } catch (const NumericError& e) {
      return {false, h, detail::at_time(tm, e.what())};
    }
    const std::string bad = detail::non_finite_value(*system_, probe_, qdd_m_, yd_m_);
    if (!bad.empty()) return {false, h, detail::at_time(tm, bad)};
    momentum_rate(tm, qm_, vm_, ym_, qdd_m_, M_, pdot_);

    // Change of this update, relative to q_scale for q (never |q|, which winds up)
    // and to the size of p and y.
    double change = 0.0;
    auto update = [&change](Vector& x, const Vector& next, const Vector* scale) {
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        const double size = scale != nullptr ? (*scale)[i] : std::max(1.0, std::abs(next[i]));
        change = std::max(change, std::abs(next[i] - x[i]) / size);
      }
      x = next;
    };
    update(q1_, current_.q + h * vm_, &q_scale_);
    update(p1_, p_ + h * pdot_, nullptr);
    update(y1_, current_.y + h * yd_m_, nullptr);
    ++stats_.newton_iterations;
    // Converged at rounding level, or stalled at the level of the rounding noise of
    // M and Ṁ·v from residual differences (the change no longer halves).
    const bool converged = change <= 4.0 * eps || (change < 1e-9 && change > 0.5 * previous_change);
    if (converged) {
      const std::string failure = end_of_step(t0 + h);
      return {failure.empty(), h, failure};
    }
    if (!std::isfinite(change)) break;
    previous_change = change;
  }
  return {false, h,
          detail::at_time(t0 + h, fmt::format("midpoint iteration did not converge in {} iterations "
                                              "(step {} too large for a fixed-point iteration?)",
                                              options_.max_newton_iterations, h))};
}

}  // namespace

std::unique_ptr<Integrator> make_midpoint(IntegratorOptions options) {
  return std::make_unique<Midpoint>(std::move(options));
}

}  // namespace symdyn::runtime
