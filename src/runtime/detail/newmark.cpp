#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <symdyn/runtime/detail/lu_solver.hpp>
#include <symdyn/runtime/detail/newmark.hpp>
#include <symdyn/runtime/detail/stepping_integrator.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

namespace {

struct Coefficients {
  const char* name;
  double am;     // weight of the old algorithmic acceleration
  double af;     // weight of the old acceleration
  double beta;   // position weight of the new algorithmic acceleration
  double gamma;  // velocity weight of the new algorithmic acceleration
};

constexpr double eps = std::numeric_limits<double>::epsilon();

// The error test's bound is never below this many roundings of the weights: the
// iteration's rounding floor (10 roundings, rounding_norm) stays a fifth of it, and the
// estimate above its own rounding noise (bench/results/newmark.md).
constexpr double kRoundings = 50.0;

// Newton stops when its remaining error is below this part of the local error estimate.
constexpr double kNewtonFraction = 0.05;
// Contraction rates: above kRefreshRate the Jacobian is re-evaluated for the next step;
// above kSlowRate a kept Jacobian is re-evaluated at once and the iteration restarted.
// At a fixed step the iteration may have to fall many decades, from the prediction to a
// target near rounding (step halving solves the runs far below their tolerance): there
// the Jacobian is re-evaluated at the rate that would take more than two iterations,
// sqrt(target / first correction), but not below kTightestRefresh.
constexpr double kRefreshRate = 0.1;
constexpr double kTightestRefresh = 1e-3;
constexpr double kSlowRate = 0.5;
// The carried rate becomes eta^kDrift at each step (below 1: it grows).
constexpr double kDrift = 0.9;
// Step control: h·0.9·err^(-1/3) (the estimate is of order 3) within these factors; a
// growth below kKeepBelow keeps h, and the factorization with it.
constexpr double kSafety = 0.9;
constexpr double kMinFactor = 0.2;
constexpr double kMaxFactor = 5.0;
constexpr double kKeepBelow = 1.2;

class NewmarkFamily final : public detail::SteppingIntegrator {
 public:
  NewmarkFamily(IntegratorOptions options, Coefficients c)
      : SteppingIntegrator(std::move(options)),
        c_(c),
        da_((1.0 - c.af) / (1.0 - c.am)),
        beta_(c.beta * da_),
        gamma_(c.gamma * da_),
        error_q_(c.beta + 0.5 * (c.am - c.af) - 1.0 / 6.0),
        error_qd_(velocity_error_constant(c)) {}

  std::string_view name() const override { return c_.name; }

 private:
  static double velocity_error_constant(const Coefficients& c);

  void start(const State& initial) override;
  int order() const override { return 2; }  // both members of the family
  // The trapezoidal rule (newmark, and generalized-alpha at rho_infinity = 1).
  bool symmetric() const override { return c_.am == c_.af && beta_ == 0.25 && gamma_ == 0.5; }
  detail::StepOutcome attempt(double h, bool fixed) override;
  double first_step(double t_end) override;
  std::string step_limit() const override;
  double tightest_tolerance() const override;
  void interpolate(double t, State& s, Vector& qdd, Vector& yd) override;

  void probe();
  void predict(double h);
  std::string solve(double h, bool fixed);
  std::string iterate(double h, bool fixed);
  std::string consistent_accelerations();
  std::string bad_values();
  bool newton_correction(double h);
  std::string near_singular(const State& s) const;
  double correct(double h);
  void evaluate_jacobian();
  bool factor(double h);
  double rounding_norm();

  const Coefficients c_;
  const double da_;        // d a1 / d qdd1 = (1 - af)/(1 - am)
  const double beta_;      // d q1 / d qdd1 = beta·da / h²
  const double gamma_;     // d qd1 / d qdd1 = gamma·da / h
  const double error_q_;   // cq: e_q = cq·h²·(qdd1 - qdd0)
  const double error_qd_;  // cv: e_qd = cv·h³·q''''
  int n_ = 0;
  int m_ = 0;
  double scale_ = 1.0;  // the error test's bound (header), relative to the weights

  // Committed step (with current_, qdd_, yd_ of the base).
  Vector a_;                  // (n) algorithmic acceleration
  Vector slope_;              // (n) (qdd1 - qdd0)/h over the last step: q''' at its middle
  Vector yslope_;             // (m) (yd1 - yd0)/h, y''
  Vector curvature_;          // (n) second divided difference of qdd over the last two steps
  Vector ycurvature_;         // (m) the same of yd
  double h_previous_ = 0.0;   // that step; 0 at the start, where the slopes are at t0
  bool have_slopes_ = false;  // false when the start's evaluation failed
  double first_step_ = 0.0;
  bool after_rejection_ = false;

  // The step being attempted.
  State trial_;
  Vector trial_qdd_, trial_yd_, trial_a_;
  double estimate_ = 0.0;  // the error norm of the current iterate
  double floor_ = 0.0;     // a correction norm at rounding level

  // Newton: rate/(1 - rate), carried across steps (Hairer-Wanner's faccon), and the
  // largest rate measured in this attempt.
  double eta_ = 1.0;
  double rate_ = 0.0;
  double refresh_rate_ = kRefreshRate;  // of this step's iteration

  // Iteration matrix: partials and factorization.
  Matrix M_, C_, K_;   // (n x n)
  Matrix f_y_, f_yd_;  // (n x m)
  Matrix g_q_, g_qd_;  // (m x n)
  Matrix g_y_, g_yd_;  // (m x m)
  bool have_jacobian_ = false;
  bool refresh_jacobian_ = false;  // re-evaluate before the next attempt
  bool jacobian_fresh_ = false;    // evaluated during this attempt
  bool factored_ = false;
  bool hopeless_ = false;  // the last iteration met a non-finite value
  double factored_h_ = 0.0;
  Matrix S_;  // (n+m x n+m)
  LuSolver lu_;

  Vector f_, g_, rhs_, delta_;  // scratch (n), (m), (n+m), (n+m)
  Vector error_;                // scratch (2n+m)
};

// The qd error constant of the scheme (header): a_n = qdd(t_n + d·h) + c2·h²·q'''' solves
// the relation of a and qdd to second order, and qd1 - qd0 = h·((1 - gamma)·a0 + gamma·a1)
// is expanded in h with it.
double NewmarkFamily::velocity_error_constant(const Coefficients& c) {
  const double d = c.am - c.af;
  const double c2 = ((1.0 - c.af) - (1.0 - c.am) * (1.0 + d) * (1.0 + d) - c.am * d * d) / 2.0;
  return (1.0 - c.gamma) * d * d / 2.0 + c.gamma * (1.0 + d) * (1.0 + d) / 2.0 + c2 - 1.0 / 6.0;
}

void NewmarkFamily::start(const State& initial) {
  n_ = system_->num_coordinates();
  m_ = system_->num_extra_states();
  // Each step's error within sqrt(rtol) of the weights, but not below kRoundings roundings
  // of them (rtol·sqrt(rtol) >= kRoundings·eps: below rtol = 5e-10).
  const double rtol = options_.relative_tolerance;
  scale_ = std::min(1.0, std::max(std::sqrt(rtol), kRoundings * eps / rtol));
  current_ = initial;
  trial_ = initial;
  trial_qdd_ = Vector::Zero(n_);
  trial_yd_ = Vector::Zero(m_);
  trial_a_ = Vector::Zero(n_);
  f_.resize(n_);
  g_.resize(m_);
  rhs_.resize(n_ + m_);
  delta_.resize(n_ + m_);
  error_.resize(2 * n_ + m_);
  S_.resize(n_ + m_, n_ + m_);
  lu_ = LuSolver(n_ + m_);
  have_jacobian_ = false;
  refresh_jacobian_ = false;
  factored_ = false;
  h_previous_ = 0.0;
  eta_ = 1.0;
  after_rejection_ = false;
  const std::string failure = consistent_accelerations();
  if (!failure.empty()) {
    throw NumericError(
        fmt::format("{} (consistent initial accelerations, integrator '{}')", failure, name()));
  }
  qdd_ = trial_qdd_;
  yd_ = trial_yd_;
  a_ = qdd_;
  probe();
}

// Hairer and Wanner's starting step (I, II.4) for order 2 on x = (q, qd, y) with
// x' = (qd, qdd, yd), norms under the error test's weights and bound: an explicit Euler
// step of h0 = 0.01·|x|/|x'| gives x'' = (qdd, q''', y'') by a difference, and the
// first step is min(100·h0, (0.01/max(|x'|, |x''|))^(1/3)). The difference also gives
// q''' and y'' at t0, for the first step's predictor and error estimate.
void NewmarkFamily::probe() {
  const Vector& w = weights_->update(current_, current_);
  const auto norm = [&](const Vector& q, const Vector& qd, const Vector& y) {
    double sum = 0.0;
    for (int i = 0; i < n_; ++i) sum += std::pow(q[i] / w[i], 2) + std::pow(qd[i] / w[n_ + i], 2);
    for (int j = 0; j < m_; ++j) sum += std::pow(y[j] / w[2 * n_ + j], 2);
    return std::sqrt(sum / std::max(1, 2 * n_ + m_)) / scale_;
  };
  const double d0 = norm(current_.q, current_.qd, current_.y);
  const double d1 = norm(current_.qd, qdd_, yd_);
  const double h0 = d0 < 1e-5 || d1 < 1e-5 ? 1e-6 : 0.01 * d0 / d1;
  State s = current_;
  s.t += h0;
  s.q += h0 * current_.qd;
  s.qd += h0 * qdd_;
  s.y += h0 * yd_;
  Vector qdd(n_), yd(m_);
  have_slopes_ = false;
  try {
    accelerations(s, qdd, yd);
    have_slopes_ = qdd.allFinite() && yd.allFinite();
  } catch (const NumericError&) {
  }
  curvature_ = Vector::Zero(n_);
  ycurvature_ = Vector::Zero(m_);
  if (!have_slopes_) {
    slope_ = Vector::Zero(n_);
    yslope_ = Vector::Zero(m_);
    first_step_ = 0.0;
    return;
  }
  slope_ = (qdd - qdd_) / h0;
  yslope_ = (yd - yd_) / h0;
  const double d2 = norm(qdd_, slope_, yslope_);
  const double d = std::max(d1, d2);
  const double h1 = d <= 1e-15 ? std::max(1e-6, 1e-3 * h0) : std::cbrt(0.01 / d);
  first_step_ = std::min(100.0 * h0, h1);
}

double NewmarkFamily::first_step(double t_end) {
  const double span = t_end - current_.t;
  return first_step_ > 0.0 ? std::min(first_step_, span) : 1e-3 * span;
}

// Below it, the error test's bound is kRoundings roundings whatever the tolerance (start()).
double NewmarkFamily::tightest_tolerance() const {
  return std::cbrt(kRoundings * eps * kRoundings * eps);
}

// The component of the last error estimate furthest above its weight.
std::string NewmarkFamily::step_limit() const {
  if (!(estimate_ > 0.0)) return {};
  Eigen::Index k = 0;
  error_.cwiseQuotient(weights_->weights()).cwiseAbs().maxCoeff(&k);
  const int i = static_cast<int>(k);
  if (i < 2 * n_) {
    return fmt::format("the local error of {} of coordinate '{}'", i < n_ ? "q" : "qd",
                       system_->coordinate_name(i % n_));
  }
  return fmt::format("the local error of extra state '{}'", system_->extra_state_name(i - 2 * n_));
}

// The Hermite interpolants (stepping_integrator.hpp), but qdd linear between the step's
// ends. The same for Newmark: its (qd1 - qd0)/h is the mean of qdd0 and qdd1, so that the
// derivative of the cubic of qd is linear. Generalized-alpha's qd follows the algorithmic
// acceleration instead, and the cubic's derivative would carry the difference.
void NewmarkFamily::interpolate(double t, State& s, Vector& qdd, Vector& yd) {
  SteppingIntegrator::interpolate(t, s, qdd, yd);
  const double th = (t - previous_.t) / (current_.t - previous_.t);
  qdd = previous_qdd_ + th * (qdd_ - previous_qdd_);
}

// qdd1 and yd1 extrapolated from the last two steps (a parabola through qdd, or at the
// start a line with the slope at t0), q1, qd1, y1 from the formulas of the scheme.
// Generalized-alpha's a0 lags qdd0 by d·h_previous (d = am - af; at the start
// h_previous = 0, a0 = qdd0): the step of h takes a0 + d·(h - h_previous)·q'''(t0), which
// lags by d·h. Otherwise each change of step, and the start, would make an error of
// O(h²·|h - h_previous|·q''') that the estimate does not see.
void NewmarkFamily::predict(double h) {
  trial_.t = current_.t + h;
  const double h2 = h * h;
  const double hh = h * (h + h_previous_);
  const double lag = (c_.am - c_.af) * (h - h_previous_);
  for (int i = 0; i < n_; ++i) {
    const double qdd = qdd_[i] + h * slope_[i] + hh * curvature_[i];
    const double a0 = a_[i] + lag * (slope_[i] + h_previous_ * curvature_[i]);
    const double a = ((1.0 - c_.af) * qdd + c_.af * qdd_[i] - c_.am * a0) / (1.0 - c_.am);
    trial_qdd_[i] = qdd;
    trial_a_[i] = a;
    trial_.q[i] = current_.q[i] + h * current_.qd[i] + h2 * ((0.5 - c_.beta) * a0 + c_.beta * a);
    trial_.qd[i] = current_.qd[i] + h * ((1.0 - c_.gamma) * a0 + c_.gamma * a);
  }
  for (int j = 0; j < m_; ++j) {
    const double yd = yd_[j] + h * yslope_[j] + hh * ycurvature_[j];
    trial_yd_[j] = yd;
    trial_.y[j] = current_.y[j] + 0.5 * h * (yd_[j] + yd);
  }
}

// Applies the Newton correction delta_ = (dqdd, dyd) to every quantity tied to it.
// Returns the correction's norm and sets estimate_ (and error_) to the local error
// estimate of the corrected iterate (header), both in the error test's norm: q from this
// step's slope of qdd, qd and y from the change of slope since the step before.
double NewmarkFamily::correct(double h) {
  const double bq = beta_ * h * h, gq = gamma_ * h, hy = 0.5 * h;
  for (int i = 0; i < n_; ++i) {
    const double d = delta_[i];
    trial_qdd_[i] -= d;
    trial_a_[i] -= da_ * d;
    trial_.q[i] -= bq * d;
    trial_.qd[i] -= gq * d;
  }
  for (int j = 0; j < m_; ++j) {
    trial_yd_[j] -= delta_[n_ + j];
    trial_.y[j] -= hy * delta_[n_ + j];
  }
  const Vector& w = weights_->update(current_, trial_);
  const double h2 = h * h;
  const double h3 = h2 * h;
  // q'''' = (slope1 - slope0)/((h + h_previous)/2); without the start's slopes, slope1/h
  // (h·q''' bounds h²·q'''' for small steps).
  const double spacing = have_slopes_ || h_previous_ > 0.0 ? 0.5 * (h + h_previous_) : h;
  const auto square = [](double x) { return x * x; };
  double correction = 0.0, error = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double d = delta_[i];
    correction += square(bq * d / w[i]) + square(gq * d / w[n_ + i]);
    const double change = trial_qdd_[i] - qdd_[i];
    error_[i] = error_q_ * h2 * change;
    error_[n_ + i] = error_qd_ * h3 * (change / h - slope_[i]) / spacing;
    error += square(error_[i] / w[i]) + square(error_[n_ + i] / w[n_ + i]);
  }
  for (int j = 0; j < m_; ++j) {
    const int k = 2 * n_ + j;
    correction += square(hy * delta_[n_ + j] / w[k]);
    error_[k] = h3 / 12.0 * ((trial_yd_[j] - yd_[j]) / h - yslope_[j]) / spacing;
    error += square(error_[k] / w[k]);
  }
  const double count = std::max(1, 2 * n_ + m_);
  estimate_ = std::sqrt(error / count) / scale_;
  return std::sqrt(correction / count) / scale_;
}

// A correction of 10 roundings of every component of x (or of its weight, if larger)
// in the error test's norm: iterating below it changes nothing.
double NewmarkFamily::rounding_norm() {
  const Vector& w = weights_->weights();
  double sum = 0.0;
  for (int i = 0; i < n_; ++i) {
    sum += std::pow(std::max(std::abs(trial_.q[i]), w[i]) / w[i], 2) +
           std::pow(std::max(std::abs(trial_.qd[i]), w[n_ + i]) / w[n_ + i], 2);
  }
  for (int j = 0; j < m_; ++j)
    sum += std::pow(std::max(std::abs(trial_.y[j]), w[2 * n_ + j]) / w[2 * n_ + j], 2);
  return 10.0 * eps * std::sqrt(sum / std::max(1, 2 * n_ + m_)) / scale_;
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
  refresh_jacobian_ = false;
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

// False when the iteration matrix is singular.
bool NewmarkFamily::factor(double h) {
  S_.topLeftCorner(n_, n_) = M_ + (gamma_ * h) * C_ + (beta_ * h * h) * K_;
  if (m_ > 0) {
    S_.topRightCorner(n_, m_) = f_yd_ + (0.5 * h) * f_y_;
    S_.bottomLeftCorner(m_, n_) = (gamma_ * h) * g_qd_ + (beta_ * h * h) * g_q_;
    S_.bottomRightCorner(m_, m_) = g_yd_ + (0.5 * h) * g_y_;
  }
  factored_ = lu_.factor(S_);
  factored_h_ = h;
  return factored_;
}

// The first non-finite value of the iterate or its residual, named ("" if none).
std::string NewmarkFamily::bad_values() {
  std::string bad = detail::non_finite_value(*system_, trial_, trial_qdd_, trial_yd_);
  if (bad.empty()) bad = detail::non_finite_entry(*system_, "residual f", f_, false);
  if (bad.empty()) bad = detail::non_finite_entry(*system_, "residual g", g_, true);
  return bad;
}

// At t0 (h = 0: q, qd, y stay), the accelerations that satisfy the equations, Newton
// on (qdd, yd) from zero, converged to 1e-3 of the error test's bound relative to
// atol + rtol·|x| (EasyDyn's start).
std::string NewmarkFamily::consistent_accelerations() {
  evaluate_jacobian();
  const double kappa = std::max(10.0 * eps / options_.relative_tolerance, 1e-3 * scale_);
  const auto weight = [this](double x) {
    return options_.absolute_tolerance + options_.relative_tolerance * std::abs(x);
  };
  double previous = 0.0;
  for (int k = 1; k <= options_.max_newton_iterations; ++k) {
    const bool finite = trial_.q.allFinite() && trial_.qd.allFinite() && trial_.y.allFinite();
    if (finite) residual(trial_, trial_qdd_, trial_yd_, f_, g_);
    if (!finite || !f_.allFinite() || !g_.allFinite())
      return detail::at_time(trial_.t, bad_values());
    if (!newton_correction(0.0)) return detail::at_time(trial_.t, "singular iteration matrix");
    trial_qdd_ -= delta_.head(n_);
    trial_yd_ -= delta_.tail(m_);
    double sum = 0.0;
    for (int i = 0; i < n_; ++i) sum += std::pow(delta_[i] / weight(trial_qdd_[i]), 2);
    for (int j = 0; j < m_; ++j) sum += std::pow(delta_[n_ + j] / weight(trial_yd_[j]), 2);
    const double norm = std::sqrt(sum / std::max(1, n_ + m_));
    if (norm <= kappa) return {};
    if (k >= 2) {
      const double rate = norm / previous;
      if (rate < 1.0 && rate / (1.0 - rate) * norm <= kappa) return {};
      if (rate >= 1.0) {
        return detail::at_time(trial_.t, fmt::format("Newton iteration diverges (rate {:.3g}){}",
                                                     rate, near_singular(trial_)));
      }
    }
    previous = norm;
  }
  return detail::at_time(trial_.t, fmt::format("Newton iteration did not converge in {} iterations",
                                               options_.max_newton_iterations));
}

// ": <the system's reason>" where the equations are nearly singular at s, else "".
std::string NewmarkFamily::near_singular(const State& s) const {
  const auto why = system_->explain_near_singular(s);
  return why ? ", near a singular configuration: " + *why : std::string();
}

// delta_ = S⁻¹·(f, g), S the iteration matrix for h (refactored when h changed). False
// when S is singular or the correction not finite.
bool NewmarkFamily::newton_correction(double h) {
  if ((!factored_ || factored_h_ != h) && !factor(h)) return false;
  if (m_ == 0) {
    lu_.solve(f_, delta_);
  } else {
    rhs_ << f_, g_;
    lu_.solve(rhs_, delta_);
  }
  ++stats_.newton_iterations;
  return delta_.allFinite();
}

// Modified Newton from the current trial values. "" when converged, else why not;
// "slow" asks the caller for a fresh Jacobian.
std::string NewmarkFamily::iterate(double h, bool fixed) {
  hopeless_ = false;
  double previous = 0.0;
  for (int k = 1; k <= options_.max_newton_iterations; ++k) {
    const bool finite = trial_.q.allFinite() && trial_.qd.allFinite() && trial_.y.allFinite() &&
                        trial_qdd_.allFinite() && trial_yd_.allFinite();
    if (finite) residual(trial_, trial_qdd_, trial_yd_, f_, g_);
    if (!finite || !f_.allFinite() || !g_.allFinite()) {
      hopeless_ = true;  // a fresh Jacobian would not make it finite
      return bad_values();
    }
    if (!newton_correction(h)) return "singular iteration matrix" + near_singular(trial_);
    const double norm = correct(h);
    if (k == 1) floor_ = rounding_norm();
    if (norm <= floor_) return {};
    // The remaining error against a part of the step's own error (at a fixed step, of
    // at most the error test's bound: such a step is not refused for its error).
    const double target =
        std::max(kNewtonFraction * (fixed ? std::min(estimate_, 1.0) : estimate_), floor_);
    if (k == 1) {
      refresh_rate_ = fixed ? std::clamp(std::sqrt(target / norm), kTightestRefresh, kRefreshRate)
                            : kRefreshRate;
    }
    if (k >= 2) {
      const double rate = norm / previous;
      rate_ = std::max(rate_, rate);
      if (rate >= 1.0) {
        return jacobian_fresh_ ? fmt::format("Newton iteration diverges (rate {:.3g}){}", rate,
                                             near_singular(trial_))
                               : "slow";
      }
      if (rate > kSlowRate && !jacobian_fresh_) return "slow";
      eta_ = rate / (1.0 - rate);
    }
    if (eta_ * norm <= target) return {};
    previous = norm;
  }
  return fmt::format("Newton iteration did not converge in {} iterations",
                     options_.max_newton_iterations);
}

// Solves the step's equations from the prediction; on trouble with a Jacobian
// kept from earlier steps, re-evaluates it and starts again from the prediction.
std::string NewmarkFamily::solve(double h, bool fixed) {
  if (!have_jacobian_ || refresh_jacobian_) evaluate_jacobian();
  std::string trouble = iterate(h, fixed);
  if (trouble.empty() || jacobian_fresh_ || hopeless_) {
    return trouble.empty() ? trouble : detail::at_time(trial_.t, trouble);
  }
  predict(h);
  evaluate_jacobian();
  eta_ = 1.0;
  trouble = iterate(h, fixed);
  return trouble.empty() ? trouble : detail::at_time(trial_.t, trouble);
}

detail::StepOutcome NewmarkFamily::attempt(double h, bool fixed) {
  jacobian_fresh_ = false;
  rate_ = 0.0;
  // Unmeasured, the carried rate drifts towards 1 (Hairer-Wanner): a second iteration
  // measures it again every few steps. RADAU5 takes eta^0.8; eta^0.9 measures less often
  // at the same errors (bench/results/newmark.md, "Choices measured").
  eta_ = std::exp(kDrift * std::log(std::max(eta_, eps)));
  predict(h);
  std::string failure;
  try {
    failure = solve(h, fixed);
  } catch (const NumericError& e) {  // the system's own report of a bad state
    failure = detail::at_time(trial_.t, e.what());
  }
  if (!failure.empty()) {
    after_rejection_ = true;
    return {false, h / 4.0, failure};
  }
  const double error = estimate_;
  // The step that would meet the test: h·err^(-1/3).
  const double ratio = kSafety / std::cbrt(std::max(error, 1e-10));
  if (!fixed && error > 1.0) {
    after_rejection_ = true;
    return {false, h * std::max(kMinFactor, ratio), {}};
  }
  // Divided differences for the next prediction and error estimate (at the start, the
  // slopes are at t0 and the step's own is the second point).
  const double spacing = have_slopes_ || h_previous_ > 0.0 ? h + h_previous_ : 0.0;
  const auto advance = [&](const Vector& x0, const Vector& x1, Vector& slope, Vector& curvature) {
    for (Eigen::Index i = 0; i < x0.size(); ++i) {
      const double s = (x1[i] - x0[i]) / h;
      curvature[i] = spacing > 0.0 ? (s - slope[i]) / spacing : 0.0;
      slope[i] = s;
    }
  };
  advance(qdd_, trial_qdd_, slope_, curvature_);
  advance(yd_, trial_yd_, yslope_, ycurvature_);
  h_previous_ = h;
  // The trial becomes the step (its old values are all overwritten by the next prediction).
  std::swap(current_, trial_);
  std::swap(qdd_, trial_qdd_);
  std::swap(yd_, trial_yd_);
  std::swap(a_, trial_a_);
  if (rate_ > refresh_rate_) refresh_jacobian_ = true;
  double factor = std::clamp(ratio, kMinFactor, after_rejection_ ? 1.0 : kMaxFactor);
  if (factor >= 1.0 && factor < kKeepBelow) factor = 1.0;
  after_rejection_ = false;
  return {true, h * factor, {}};
}

}  // namespace

std::unique_ptr<Integrator> make_newmark(IntegratorOptions options) {
  return std::make_unique<NewmarkFamily>(std::move(options),
                                         Coefficients{"newmark", 0.0, 0.0, 0.25, 0.5});
}

std::unique_ptr<Integrator> make_generalized_alpha(IntegratorOptions options) {
  const double rho = options.rho_infinity;
  if (!(rho >= 0.0 && rho <= 1.0)) {
    throw OptionError(
        fmt::format("integrator 'generalized-alpha': rho_infinity {} is outside [0, 1]", rho));
  }
  const double am = (2.0 * rho - 1.0) / (rho + 1.0);
  const double af = rho / (rho + 1.0);
  const double gamma = 0.5 - am + af;
  const double beta = 0.25 * (1.0 - am + af) * (1.0 - am + af);
  return std::make_unique<NewmarkFamily>(std::move(options),
                                         Coefficients{"generalized-alpha", am, af, beta, gamma});
}

}  // namespace symdyn::runtime
