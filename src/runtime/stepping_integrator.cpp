#include "runtime/stepping_integrator.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "runtime/errors.hpp"

namespace symdyn::runtime::detail {

void SteppingIntegrator::interpolate(double t, State&, Vector&, Vector&) {
  throw NumericError(at_time(t, fmt::format("integrator '{}' has no dense output", name())));
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
    return options_.initial_step;
  }
  const double h = options_.initial_step > 0.0 ? options_.initial_step : first_step(t_end);
  return std::clamp(h, options_.min_step, options_.max_step);
}

// Delivers the output instants reached by the step that ended at current_.t:
// the one hit exactly, or (dense output) every instant in (t_previous, t].
void SteppingIntegrator::deliver(double t_previous, std::size_t& next_output) {
  if (output_every_step()) {
    emit(*system_, current_, qdd_, yd_);
    return;
  }
  const auto& instants = output_instants();
  State s;
  Vector qdd, yd;
  while (next_output < instants.size() && instants[next_output] <= current_.t) {
    const double ti = instants[next_output++];
    if (ti == current_.t) {
      emit(*system_, current_, qdd_, yd_);
    } else if (ti > t_previous) {
      interpolate(ti, s, qdd, yd);
      emit(*system_, s, qdd, yd);
    }
  }
}

State SteppingIntegrator::run(DynamicSystem& system, const State& initial, double t_end) {
  system_ = &system;
  const bool fixed = options_.fixed_step || fixed_step_only();
  // Steps other methods would take and we shorten to hit an output instant exactly.
  const bool hit_instants = !has_dense_output();
  start(initial);
  double h = initial_step(t_end);
  emit(system, current_, qdd_, yd_);
  progress(current_.t);

  std::size_t next_output = 0;
  std::string last_failure;
  while (current_.t < t_end) {
    // The limit this step must not cross: the next output instant or t_end.
    double limit = t_end;
    if (hit_instants && next_output < output_instants().size()) limit = output_instants()[next_output];
    double step = h;
    bool shortened = false;
    // Landing within 1e-6 steps of the limit counts as reaching it: no sliver step after.
    if (current_.t + step * (1.0 + 1e-6) >= limit) {
      step = limit - current_.t;
      shortened = true;
    }
    const double t_previous = current_.t;
    StepOutcome outcome = attempt(step, fixed);
    if (!outcome.accepted) {
      ++stats_.rejected_steps;
      if (!outcome.failure.empty()) last_failure = outcome.failure;
      if (fixed) {
        throw NumericError(fmt::format("{} (fixed step {} from t = {})", outcome.failure, step,
                                       t_previous));
      }
      h = std::min(outcome.next_step, options_.max_step);
      if (h < options_.min_step) {
        throw NumericError(at_time(
            t_previous,
            fmt::format("step size {} below min_step {} (integrator '{}'){}", h, options_.min_step,
                        name(), last_failure.empty() ? "" : "; last failure: " + last_failure)));
      }
      continue;
    }
    ++stats_.steps;
    if (shortened) current_.t = limit;  // exactly, whatever the rounding of t + step
    const std::string bad = non_finite_value(system, current_, qdd_, yd_);
    if (!bad.empty()) throw NumericError(at_time(current_.t, bad));
    deliver(t_previous, next_output);
    progress(current_.t);
    if (fixed) continue;
    // A step shortened for an output says nothing against the step before it.
    h = shortened && outcome.next_step >= step ? std::max(outcome.next_step, h) : outcome.next_step;
    h = std::min(h, options_.max_step);
    if (h < options_.min_step) {
      throw NumericError(at_time(current_.t, fmt::format("step size {} below min_step {} (integrator '{}')",
                                                         h, options_.min_step, name())));
    }
  }
  return current_;
}

}  // namespace symdyn::runtime::detail
