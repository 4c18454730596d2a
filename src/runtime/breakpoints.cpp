#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include <symdyn/runtime/breakpoints.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

namespace {

void check_breakpoints(const std::vector<double>& breakpoints, double t_begin, double t_end) {
  double previous = t_begin;
  for (std::size_t k = 0; k < breakpoints.size(); ++k) {
    const double t = breakpoints[k];
    if (!(t > previous && t < t_end)) {
      throw OptionError(
          fmt::format("breakpoint {} at t = {}: breakpoints must increase strictly inside ({}, {})",
                      k, t, t_begin, t_end));
    }
    previous = t;
  }
}

// The work of the segments summed; with global_tolerance, the estimates of their
// errors too (each segment starts from the previous one's result, so an error
// carried over is in neither estimate: the sum assumes it is carried unamplified).
void add_segment(Statistics& sum, const Statistics& s, bool first, double global_tolerance) {
  if (first) {
    sum.global_error_estimate = s.global_error_estimate;
    sum.runs = s.runs;
    sum.extrapolated = s.extrapolated;
  } else {
    sum.global_error_estimate += s.global_error_estimate;
    sum.runs = std::max(sum.runs, s.runs);
    sum.extrapolated = sum.extrapolated && s.extrapolated;
  }
  sum.last_relative_tolerance = s.last_relative_tolerance;
  sum.last_step = s.last_step;
  sum.global_tolerance_met =
      global_tolerance > 0.0 && sum.global_error_estimate <= global_tolerance;
  sum.add_work(s);
}

}  // namespace

SegmentedRun integrate_with_breakpoints(Integrator& integrator, DynamicSystem& system,
                                        const State& initial,
                                        const std::vector<double>& breakpoints, double t_end,
                                        const BreakpointCallback& at_breakpoint) {
  check_breakpoints(breakpoints, initial.t, t_end);
  // Each segment but the first starts by delivering its initial state: drop it.
  const OutputCallback user = integrator.options().on_output;
  bool skip_first = false;
  if (user) {
    integrator.options().on_output = [&](const State& s, const Vector& qdd, const Vector& yd) {
      if (std::exchange(skip_first, false)) return;
      user(s, qdd, yd);
    };
  }
  SegmentedRun run;
  run.final = initial;
  try {
    for (std::size_t k = 0; k <= breakpoints.size(); ++k) {
      const double t_stop = k < breakpoints.size() ? breakpoints[k] : t_end;
      skip_first = k > 0;
      run.final = integrator.integrate(system, run.final, t_stop);
      add_segment(run.statistics, integrator.statistics(), k == 0,
                  integrator.options().global_tolerance);
      ++run.segments;
      if (k < breakpoints.size()) {
        run.final.t = t_stop;  // exactly, whatever the last step's rounding
        if (at_breakpoint) at_breakpoint(k, run.final);
      }
    }
  } catch (...) {
    integrator.options().on_output = user;
    throw;
  }
  integrator.options().on_output = user;
  return run;
}

}  // namespace symdyn::runtime
