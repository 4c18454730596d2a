#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <symdyn/runtime/detail/stepping_integrator.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime::detail {

namespace {

// Hermite bases on [0, 1] as coefficients of 1, th, ..., th^5. Quintic, for
// (x0, h·x0', h²·x0'', x1, h·x1', h²·x1''); cubic, for (x0, h·x0', x1, h·x1').
constexpr double quintic[6][6] = {{1, 0, 0, -10, 15, -6},       {0, 1, 0, -6, 8, -3},
                                  {0, 0, 0.5, -1.5, 1.5, -0.5}, {0, 0, 0, 10, -15, 6},
                                  {0, 0, 0, -4, 7, -3},         {0, 0, 0, 0.5, -1, 0.5}};
constexpr double cubic[4][6] = {
    {1, 0, -3, 2, 0, 0}, {0, 1, -2, 1, 0, 0}, {0, 0, 3, -2, 0, 0}, {0, 0, -1, 1, 0, 0}};

// The value and the first two derivatives in th of a polynomial of degree <= 5.
std::array<double, 3> evaluate(const double (&c)[6], double th) {
  double p = 0.0, dp = 0.0, ddp = 0.0;
  for (int k = 5; k >= 0; --k) {
    ddp = ddp * th + 2.0 * dp;
    dp = dp * th + p;
    p = p * th + c[k];
  }
  return {p, dp, ddp};
}

std::string limited_by(const std::string& limit) {
  return limit.empty() ? limit : "; the step is set by " + limit;
}

// The largest rate |qd_i| or extra state |y_j| of s, and its index (qd first, then y).
std::pair<double, Eigen::Index> largest_rate(const State& s) {
  std::pair<double, Eigen::Index> largest{0.0, -1};
  for (Eigen::Index i = 0; i < s.qd.size() + s.y.size(); ++i) {
    const double v = std::abs(i < s.qd.size() ? s.qd[i] : s.y[i - s.qd.size()]);
    if (v > largest.first) largest = {v, i};
  }
  return largest;
}

}  // namespace

void SteppingIntegrator::interpolate(double t, State& s, Vector& qdd, Vector& yd) {
  const State& a = previous_;
  const State& b = current_;
  const double h = b.t - a.t;
  const double th = (t - a.t) / h;
  std::array<std::array<double, 3>, 6> p;
  for (int k = 0; k < 6; ++k) p[k] = evaluate(quintic[k], th);
  std::array<std::array<double, 3>, 4> c;
  for (int k = 0; k < 4; ++k) c[k] = evaluate(cubic[k], th);
  // q and qd = dq/dt = (1/h)·dq/dth from the quintic.
  s.q = p[0][0] * a.q + (h * p[1][0]) * a.qd + (h * h * p[2][0]) * previous_qdd_ + p[3][0] * b.q +
        (h * p[4][0]) * b.qd + (h * h * p[5][0]) * qdd_;
  s.qd = (p[0][1] * a.q + (h * p[1][1]) * a.qd + (h * h * p[2][1]) * previous_qdd_ + p[3][1] * b.q +
          (h * p[4][1]) * b.qd + (h * h * p[5][1]) * qdd_) /
         h;
  // qdd from the cubic of qd, not from the quintic's second derivative, which would
  // divide the step's local error in q by h².
  qdd =
      (c[0][1] * a.qd + (h * c[1][1]) * previous_qdd_ + c[2][1] * b.qd + (h * c[3][1]) * qdd_) / h;
  s.y = c[0][0] * a.y + (h * c[1][0]) * previous_yd_ + c[2][0] * b.y + (h * c[3][0]) * yd_;
  yd = (c[0][1] * a.y + (h * c[1][1]) * previous_yd_ + c[2][1] * b.y + (h * c[3][1]) * yd_) / h;
  s.t = t;
}

void SteppingIntegrator::accelerations(const State& s, Vector& qdd, Vector& yd) {
  ++stats_.rhs_evaluations;
  system_->accelerations(s, qdd, yd);
}

void SteppingIntegrator::residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                                  Vector& g) {
  ++stats_.residual_evaluations;
  system_->residual(s, qdd, yd, f, g);
}

double SteppingIntegrator::initial_step(double t_end) {
  if (options_.fixed_step || fixed_step_only()) {
    if (!(options_.initial_step > 0.0)) {
      throw OptionError(fmt::format(
          "integrator '{}': a fixed-step run needs initial_step > 0 (the step)", name()));
    }
    // The number of steps is known: refuse at once what would not finish.
    const double steps = (t_end - current_.t) / options_.initial_step;
    if (steps > static_cast<double>(options_.max_steps)) {
      throw OptionError(
          fmt::format("integrator '{}': a fixed step of {:g} s from t = {:g} to {:g} takes {:.3g} "
                      "steps, over max_steps {}",
                      name(), options_.initial_step, current_.t, t_end, steps, options_.max_steps));
    }
    return options_.initial_step;
  }
  const double h = options_.initial_step > 0.0 ? options_.initial_step : first_step(t_end);
  return std::clamp(h, options_.min_step, options_.max_step);
}

// Delivers the output instants reached by the step that ended at current_.t:
// every instant in (t_previous, t], interpolated unless it is the step's end.
void SteppingIntegrator::deliver(double t_previous, std::size_t& next_output) {
  if (output_every_step()) {
    emit(*system_, current_, qdd_, yd_);
    return;
  }
  const auto& instants = output_instants();
  while (next_output < instants.size() && instants[next_output] <= current_.t) {
    const double ti = instants[next_output++];
    if (ti == current_.t) {
      emit(*system_, current_, qdd_, yd_);
    } else if (ti > t_previous) {
      interpolate(ti, dense_, dense_qdd_, dense_yd_);
      emit(*system_, dense_, dense_qdd_, dense_yd_);
    }
  }
}

// A fixed step has no error test: a step too large for the motion amplifies it
// step after step until a value is not finite, wherever that shows first (a
// tyre's force, a kinematic quantity). Rates grown a thousandfold since the
// start, to a size the start did not have, blame the step; otherwise the failure
// is reported as met, with the step.
void SteppingIntegrator::fixed_step_failed(const std::string& failure, double step,
                                           const State& initial) const {
  const auto [before, index] = largest_rate(previous_);
  const double start = largest_rate(initial).first;
  if (before > 1e3 * std::max(start, 1.0) && index >= 0) {
    const int n = static_cast<int>(previous_.qd.size());
    const std::string what =
        index < n ? fmt::format("the rate of coordinate '{}'",
                                system_->coordinate_name(static_cast<int>(index)))
                  : fmt::format("extra state '{}'",
                                system_->extra_state_name(static_cast<int>(index) - n));
    throw NumericError(fmt::format(
        "t = {}: the run diverged at its fixed step of {:g} s: {} grew to {:.3g} (the largest at "
        "t = {} was {:.3g}); take a smaller step, or an adaptive integrator (then: {})",
        previous_.t, step, what, before, initial.t, start, failure));
  }
  throw NumericError(
      fmt::format("{} (fixed step {:g} from t = {}: if a smaller step passes, the "
                  "step was too large for the motion)",
                  failure, step, previous_.t));
}

State SteppingIntegrator::run(DynamicSystem& system, const State& initial, double t_end) {
  system_ = &system;
  const bool fixed = options_.fixed_step || fixed_step_only();
  weights_.emplace(options_, name(), system.num_coordinates(), system.num_extra_states());
  start(initial);
  double h = initial_step(t_end);
  emit(system, current_, qdd_, yd_);
  progress(current_.t);

  std::size_t next_output = 0;
  std::string last_failure;
  FailureStreak streak;
  while (current_.t < t_end) {
    if (stats_.steps + stats_.rejected_steps >= options_.max_steps) {
      throw NumericError(
          at_time(current_.t, fmt::format("{} step attempts reached max_steps (integrator '{}')",
                                          options_.max_steps, name())));
    }
    const double limit = t_end;
    double step = h;
    bool shortened = false;
    // Landing within 1e-6 steps of the limit counts as reaching it: no sliver step after.
    if (current_.t + step * (1.0 + 1e-6) >= limit) {
      step = limit - current_.t;
      shortened = true;
    }
    const double t_previous = current_.t;
    previous_ = current_;
    previous_qdd_ = qdd_;
    previous_yd_ = yd_;
    StepOutcome outcome = attempt(step, fixed);
    if (!outcome.accepted) {
      ++stats_.rejected_steps;
      if (!outcome.failure.empty()) {
        last_failure = outcome.failure;
        if (streak.failed(step)) {
          throw NumericError(fmt::format(
              "{} (integrator '{}': {} failed steps from {:g} s down to {:g} s without recovering: "
              "the solution runs into a place it cannot pass)",
              outcome.failure, name(), streak.count(), streak.first_step(), step));
        }
      }
      if (fixed) fixed_step_failed(outcome.failure, step, initial);
      h = std::min(outcome.next_step, options_.max_step);
      if (h < options_.min_step) {
        throw NumericError(
            at_time(t_previous,
                    fmt::format("step size {} below min_step {} (integrator '{}'){}{}", h,
                                options_.min_step, name(), limited_by(step_limit()),
                                last_failure.empty() ? "" : "; last failure: " + last_failure)));
      }
      continue;
    }
    ++stats_.steps;
    streak.accepted(step);
    if (shortened) current_.t = limit;  // exactly, whatever the rounding of t + step
    const std::string bad = non_finite_value(system, current_, qdd_, yd_);
    if (!bad.empty()) throw NumericError(at_time(current_.t, bad));
    system.check_step(previous_, current_);
    deliver(t_previous, next_output);
    progress(current_.t);
    if (fixed) continue;
    // The last step, shortened to end at t_end, says nothing against the step before it.
    h = shortened && outcome.next_step >= step ? std::max(outcome.next_step, h) : outcome.next_step;
    h = std::min(h, options_.max_step);
    if (h < options_.min_step) {
      throw NumericError(
          at_time(current_.t, fmt::format("step size {} below min_step {} (integrator '{}'){}", h,
                                          options_.min_step, name(), limited_by(step_limit()))));
    }
  }
  return current_;
}

}  // namespace symdyn::runtime::detail
