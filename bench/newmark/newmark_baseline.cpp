// The previous implementation of newmark and generalized-alpha (src/runtime/newmark.cpp at
// 2dd6e1f), kept as the baseline of bench/newmark/newmark_bench.cpp: modified Newton from
// qdd1 = qdd0 stopped against the tolerance, each step's error against the tolerance itself
// (h²·|qdd1 - qdd0|/12 and divided differences), h·0.9·err^(-1/3) kept within 1.5, a first
// step of 1e-3 of the interval. Unchanged but for its names and namespace.
#include "newmark_baseline.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include <symdyn/runtime/detail/stepping_integrator.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::bench {

using namespace symdyn::runtime;

namespace {

struct Coefficients {
  const char* name;
  double am;     // weight of the old algorithmic acceleration
  double af;     // weight of the old acceleration
  double beta;   // position weight of the new algorithmic acceleration
  double gamma;  // velocity weight of the new algorithmic acceleration
};

constexpr double eps = std::numeric_limits<double>::epsilon();

class NewmarkFamily final : public detail::SteppingIntegrator {
 public:
  NewmarkFamily(IntegratorOptions options, Coefficients c)
      : SteppingIntegrator(std::move(options)),
        c_(c),
        da_((1.0 - c.af) / (1.0 - c.am)),
        beta_(c.beta * da_),
        gamma_(c.gamma * da_) {}

  std::string_view name() const override { return c_.name; }

 private:
  void start(const State& initial) override;
  detail::StepOutcome attempt(double h, bool fixed) override;
  double first_step(double t_end) override;
  int order() const override { return 2; }  // both members of the family

  void predict(double h);
  std::string solve(double h);
  std::string iterate(double h, double kappa);
  void apply(double h);
  void evaluate_jacobian();
  void factor(double h);
  double newton_norm(double h);
  double third_derivative(double r0, double r1, double r2, double h) const;
  double error_norm(double h);

  const Coefficients c_;
  const double da_;     // d a1 / d qdd1 = (1 - af)/(1 - am)
  const double beta_;   // d q1 / d qdd1 = beta·da / h²
  const double gamma_;  // d qd1 / d qdd1 = gamma·da / h
  int n_ = 0;
  int m_ = 0;

  // Committed step (with current_, qdd_, yd_ of the base).
  Vector a_;             // (n) algorithmic acceleration
  Vector qdd_previous_;  // (n) qdd one step before, for q''''
  Vector yd_previous_;   // (m) yd one step before, for y'''
  double h_previous_ = 0.0;

  // The step being attempted.
  State trial_;
  Vector trial_qdd_, trial_yd_, trial_a_;

  // Iteration matrix: partials and factorization.
  Matrix M_, C_, K_;   // (n x n)
  Matrix f_y_, f_yd_;  // (n x m)
  Matrix g_q_, g_qd_;  // (m x n)
  Matrix g_y_, g_yd_;  // (m x m)
  bool have_jacobian_ = false;
  bool jacobian_fresh_ = false;  // evaluated during this attempt
  bool factored_ = false;
  bool hopeless_ = false;  // the last iteration met a non-finite value
  double factored_h_ = 0.0;
  Matrix S_;  // (n+m x n+m)
  Eigen::PartialPivLU<Matrix> lu_;

  Vector f_, g_, rhs_, delta_;  // scratch (n), (m), (n+m), (n+m)
  Vector error_;                // scratch (2n+m)
};

void NewmarkFamily::start(const State& initial) {
  n_ = system_->num_coordinates();
  m_ = system_->num_extra_states();
  current_ = initial;
  trial_ = initial;
  trial_qdd_ = Vector::Zero(n_);
  trial_yd_ = Vector::Zero(m_);
  trial_a_ = Vector::Zero(n_);
  f_.resize(n_);
  g_.resize(m_);
  error_.resize(2 * n_ + m_);
  have_jacobian_ = false;
  factored_ = false;
  h_previous_ = 0.0;
  // h = 0: q, qd, y stay, the iteration only finds qdd and yd (EasyDyn's start).
  const std::string failure = solve(0.0);
  if (!failure.empty()) {
    throw NumericError(
        fmt::format("{} (consistent initial accelerations, integrator '{}')", failure, name()));
  }
  qdd_ = trial_qdd_;
  yd_ = trial_yd_;
  a_ = qdd_;
  qdd_previous_ = qdd_;
  yd_previous_ = yd_;
}

double NewmarkFamily::first_step(double t_end) {
  return 1e-3 * (t_end - current_.t);
}

// qdd1 = qdd0, yd1 = yd0, and q1, qd1, y1 from the formulas of the scheme.
void NewmarkFamily::predict(double h) {
  trial_.t = current_.t + h;
  trial_qdd_ = qdd_;
  trial_yd_ = yd_;
  trial_a_ = (qdd_ - c_.am * a_) / (1.0 - c_.am);
  trial_.q = current_.q + h * current_.qd + (h * h) * ((0.5 - c_.beta) * a_ + c_.beta * trial_a_);
  trial_.qd = current_.qd + h * ((1.0 - c_.gamma) * a_ + c_.gamma * trial_a_);
  trial_.y = current_.y + h * yd_;
}

// Newton update by delta_ = (dqdd, dyd), moving every quantity tied to them.
void NewmarkFamily::apply(double h) {
  const auto dqdd = delta_.head(n_);
  const auto dyd = delta_.tail(m_);
  trial_qdd_ -= dqdd;
  trial_a_ -= da_ * dqdd;
  trial_.q -= (beta_ * h * h) * dqdd;
  trial_.qd -= (gamma_ * h) * dqdd;
  trial_yd_ -= dyd;
  trial_.y -= (0.5 * h) * dyd;
}

// RMS of the corrections of q, qd and y under the error weights (of qdd and yd
// themselves, relative to atol + rtol·|x|, when h = 0, where q, qd and y do not move).
double NewmarkFamily::newton_norm(double h) {
  const auto dqdd = delta_.head(n_);
  const auto dyd = delta_.tail(m_);
  if (h == 0.0) {
    const auto weight = [this](double x) {
      return options_.absolute_tolerance + options_.relative_tolerance * std::abs(x);
    };
    double sum = 0.0;
    for (int i = 0; i < n_; ++i) sum += std::pow(dqdd[i] / weight(trial_qdd_[i]), 2);
    for (int j = 0; j < m_; ++j) sum += std::pow(dyd[j] / weight(trial_yd_[j]), 2);
    return std::sqrt(sum / std::max(1, n_ + m_));
  }
  error_ << (beta_ * h * h) * dqdd, (gamma_ * h) * dqdd, (0.5 * h) * dyd;
  weights_->update(current_, trial_);
  return weights_->rms(error_);
}

void NewmarkFamily::evaluate_jacobian() {
  ++stats_.jacobian_evaluations;
  system_->jacobians(trial_, trial_qdd_, M_, C_, K_);
  const auto square = [this](const Matrix& A) { return A.rows() == n_ && A.cols() == n_; };
  if (!square(M_) || !square(C_) || !square(K_)) {
    throw ModelError(fmt::format("jacobians returned M {}x{}, C {}x{}, K {}x{}; expected {}x{}",
                                 M_.rows(), M_.cols(), C_.rows(), C_.cols(), K_.rows(), K_.cols(),
                                 n_, n_));
  }
  have_jacobian_ = true;
  jacobian_fresh_ = true;
  factored_ = false;
  if (m_ == 0) return;

  // Extra-state blocks by forward differences: d = sqrt(eps)·max(1, |x|) balances
  // truncation and rounding for a one-sided difference.
  Vector f0(n_), g0(m_), f1(n_), g1(m_);
  residual(trial_, trial_qdd_, trial_yd_, f0, g0);
  State s = trial_;
  Vector yd = trial_yd_;
  auto differentiate = [&](Vector& x, Matrix* df, Matrix* dg) {
    df->resize(n_, x.size());
    dg->resize(m_, x.size());
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      const double x0 = x[j];
      x[j] = x0 + std::sqrt(eps) * std::max(1.0, std::abs(x0));
      const double d = x[j] - x0;
      residual(s, trial_qdd_, yd, f1, g1);
      x[j] = x0;
      df->col(j) = (f1 - f0) / d;
      dg->col(j) = (g1 - g0) / d;
    }
  };
  Matrix unused;
  differentiate(s.y, &f_y_, &g_y_);
  differentiate(yd, &f_yd_, &g_yd_);
  differentiate(s.q, &unused, &g_q_);
  differentiate(s.qd, &unused, &g_qd_);
}

void NewmarkFamily::factor(double h) {
  S_.resize(n_ + m_, n_ + m_);
  S_.topLeftCorner(n_, n_) = M_ + (gamma_ * h) * C_ + (beta_ * h * h) * K_;
  if (m_ > 0) {
    S_.topRightCorner(n_, m_) = f_yd_ + (0.5 * h) * f_y_;
    S_.bottomLeftCorner(m_, n_) = (gamma_ * h) * g_qd_ + (beta_ * h * h) * g_q_;
    S_.bottomRightCorner(m_, m_) = g_yd_ + (0.5 * h) * g_y_;
  }
  lu_.compute(S_);
  factored_ = true;
  factored_h_ = h;
}

// Modified Newton from the current trial values. "" when converged, else why not;
// "slow" asks the caller for a fresh Jacobian.
std::string NewmarkFamily::iterate(double h, double kappa) {
  hopeless_ = false;
  double previous = 0.0;
  for (int k = 1; k <= options_.max_newton_iterations; ++k) {
    std::string bad = detail::non_finite_value(*system_, trial_, trial_qdd_, trial_yd_);
    if (bad.empty()) {
      residual(trial_, trial_qdd_, trial_yd_, f_, g_);
      bad = detail::non_finite_entry(*system_, "residual f", f_, false);
    }
    if (bad.empty()) bad = detail::non_finite_entry(*system_, "residual g", g_, true);
    if (!bad.empty()) {
      hopeless_ = true;  // a fresh Jacobian would not make it finite
      return bad;
    }
    if (!factored_ || factored_h_ != h) factor(h);
    rhs_.resize(n_ + m_);
    rhs_ << f_, g_;
    delta_ = lu_.solve(rhs_);
    ++stats_.newton_iterations;
    if (!delta_.allFinite()) return "singular iteration matrix";
    apply(h);
    const double norm = newton_norm(h);
    if (norm <= kappa) return {};
    if (k >= 2) {
      const double rate = norm / previous;
      if (rate < 1.0 && rate / (1.0 - rate) * norm <= kappa) return {};
      if (rate > 0.25 && !jacobian_fresh_) return "slow";
      if (rate >= 1.0) return fmt::format("Newton iteration diverges (rate {:.3g})", rate);
    }
    previous = norm;
  }
  return fmt::format("Newton iteration did not converge in {} iterations",
                     options_.max_newton_iterations);
}

// Solves the step's equations from the prediction; on trouble with a Jacobian
// kept from earlier steps, re-evaluates it and starts again from the prediction.
std::string NewmarkFamily::solve(double h) {
  // Hairer and Wanner's Newton tolerance for Radau IIA, relative to the error test.
  const double rtol = options_.relative_tolerance;
  const double kappa = std::max(10.0 * eps / rtol, std::min(0.03, std::sqrt(rtol)));
  if (!have_jacobian_) evaluate_jacobian();
  std::string trouble = iterate(h, kappa);
  if (trouble.empty() || jacobian_fresh_ || hopeless_) {
    return trouble.empty() ? trouble : detail::at_time(trial_.t, trouble);
  }
  if (h > 0.0) predict(h);
  evaluate_jacobian();
  trouble = iterate(h, kappa);
  return trouble.empty() ? trouble : detail::at_time(trial_.t, trouble);
}

// Third derivative of a quantity from its rates r0 (one step before, h_previous),
// r1 (step start) and r2 (step end, after h): a divided difference over both steps;
// on the first step only the second derivative is known, and h·x'' bounds h²·x'''
// for small steps.
double NewmarkFamily::third_derivative(double r0, double r1, double r2, double h) const {
  const double slope = (r2 - r1) / h;
  return h_previous_ > 0.0 ? 2.0 / (h + h_previous_) * (slope - (r1 - r0) / h_previous_)
                           : slope / h;
}

// Local errors: q (EasyDyn) h³·q'''/12 = h²·|qdd1 - qdd0|/12; qd, trapezoidal in qdd,
// h³·q''''/12; y, trapezoidal in yd, h³·y'''/12. RMS under the error weights.
double NewmarkFamily::error_norm(double h) {
  const double h3 = h * h * h / 12.0;
  for (int i = 0; i < n_; ++i) {
    error_[i] = h * h * std::abs(trial_qdd_[i] - qdd_[i]) / 12.0;
    error_[n_ + i] = h3 * std::abs(third_derivative(qdd_previous_[i], qdd_[i], trial_qdd_[i], h));
  }
  for (int j = 0; j < m_; ++j) {
    error_[2 * n_ + j] = h3 * std::abs(third_derivative(yd_previous_[j], yd_[j], trial_yd_[j], h));
  }
  weights_->update(current_, trial_);
  return weights_->rms(error_);
}

detail::StepOutcome NewmarkFamily::attempt(double h, bool fixed) {
  jacobian_fresh_ = false;
  predict(h);
  std::string failure;
  try {
    failure = solve(h);
  } catch (const NumericError& e) {  // the system's own report of a bad state
    failure = detail::at_time(trial_.t, e.what());
  }
  if (!failure.empty()) return {false, h / 4.0, failure};
  const double error = error_norm(h);
  // The estimate is O(h³): the step that would meet the tolerance is h·err^(-1/3).
  const double ratio = 0.9 * std::pow(std::max(error, 1e-10), -1.0 / 3.0);
  if (!fixed && error > 1.0) return {false, h * std::max(0.2, ratio), {}};
  qdd_previous_ = qdd_;
  yd_previous_ = yd_;
  h_previous_ = h;
  current_ = trial_;
  qdd_ = trial_qdd_;
  yd_ = trial_yd_;
  a_ = trial_a_;
  // Growth below 1.5 is not worth refactoring the iteration matrix.
  const double next = ratio < 1.0 ? h * ratio : ratio >= 1.5 ? h * std::min(ratio, 4.0) : h;
  return {true, next, {}};
}

}  // namespace

std::unique_ptr<Integrator> make_newmark_baseline(IntegratorOptions options) {
  return std::make_unique<NewmarkFamily>(std::move(options),
                                         Coefficients{"newmark-baseline", 0.0, 0.0, 0.25, 0.5});
}

std::unique_ptr<Integrator> make_generalized_alpha_baseline(IntegratorOptions options) {
  const double rho = options.rho_infinity;
  if (!(rho >= 0.0 && rho <= 1.0)) {
    throw OptionError(
        fmt::format("integrator 'generalized-alpha': rho_infinity {} is outside [0, 1]", rho));
  }
  const double am = (2.0 * rho - 1.0) / (rho + 1.0);
  const double af = rho / (rho + 1.0);
  const double gamma = 0.5 - am + af;
  const double beta = 0.25 * (1.0 - am + af) * (1.0 - am + af);
  return std::make_unique<NewmarkFamily>(
      std::move(options), Coefficients{"generalized-alpha-baseline", am, af, beta, gamma});
}

}  // namespace symdyn::bench
