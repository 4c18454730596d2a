#pragma once
// Integration across known discontinuities (a torque switched off at t = 2 s):
// the integrator runs segment by segment, stops exactly at each breakpoint,
// lets the caller change the system (or the state) there, and restarts from
// it with a fresh step size. The output callback sees every instant once: the
// state a segment starts from was already delivered as the end of the
// previous one.
//
//   auto run = integrate_with_breakpoints(*integrator, system, initial, {2.0}, 5.0,
//                                         [&](std::size_t, State&) { motor->enable(false); });
//
// Each segment's output instants restart at its initial time (an interval of
// 0.01 after a breakpoint at 2.005 gives 2.015, 2.025, ...). Breakpoints must
// be sorted and inside (initial.t, t_end) (OptionError naming the culprit).

#include <cstddef>
#include <functional>
#include <vector>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

struct SegmentedRun {
  State final;
  Statistics statistics;  // summed over the segments (global_error_estimate too)
  int segments = 0;
};

// Called at breakpoint k with the state there (t = breakpoints[k]); may change
// the system, and the state the next segment starts from.
using BreakpointCallback = std::function<void(std::size_t k, State& s)>;

SegmentedRun integrate_with_breakpoints(Integrator& integrator, DynamicSystem& system,
                                        const State& initial,
                                        const std::vector<double>& breakpoints, double t_end,
                                        const BreakpointCallback& at_breakpoint);

}  // namespace symdyn::runtime
