#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <symdyn/runtime/detail/non_finite.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

Integrator::Integrator(IntegratorOptions options) : options_(std::move(options)) {}

void Integrator::check_options(double t_begin, double t_end) const {
  const auto& o = options_;
  auto fail = [this](const std::string& what) {
    throw OptionError(fmt::format("integrator '{}': {}", name(), what));
  };
  if (!std::isfinite(t_begin) || !std::isfinite(t_end) || !(t_end > t_begin)) {
    fail(fmt::format("the final time {} must be finite and after the initial time {}", t_end,
                     t_begin));
  }
  const auto finite_positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!finite_positive(o.relative_tolerance) || !finite_positive(o.absolute_tolerance)) {
    fail(fmt::format("tolerances must be finite and positive (relative {}, absolute {})",
                     o.relative_tolerance, o.absolute_tolerance));
  }
  if (!(o.min_step >= 0.0) || !(o.max_step > 0.0) || o.min_step > o.max_step) {
    fail(fmt::format("need 0 <= min_step <= max_step, 0 < max_step (min_step {}, max_step {})",
                     o.min_step, o.max_step));
  }
  if (!(o.initial_step >= 0.0) || !std::isfinite(o.initial_step)) {
    fail(fmt::format("initial_step {} must be finite and >= 0", o.initial_step));
  }
  if (o.initial_step > 0.0 && o.initial_step < o.min_step) {
    fail(fmt::format("initial_step {:g} is below min_step {:g}", o.initial_step, o.min_step));
  }
  if (!(o.max_steps > 0)) fail(fmt::format("max_steps {} must be positive", o.max_steps));
  if (!(o.global_tolerance >= 0.0) || !std::isfinite(o.global_tolerance)) {
    fail(fmt::format("global_tolerance {} must be finite and >= 0", o.global_tolerance));
  }

  if (o.max_newton_iterations < 1) {
    fail(fmt::format("max_newton_iterations {} must be at least 1", o.max_newton_iterations));
  }
  if (!(o.output_interval >= 0.0) || !std::isfinite(o.output_interval)) {
    fail(fmt::format("output_interval {} must be finite and >= 0", o.output_interval));
  }
  if (o.output_interval > 0.0 && !o.output_times.empty()) {
    fail("give either output_times or output_interval, not both");
  }
  for (std::size_t i = 0; i < o.output_times.size(); ++i) {
    const double ti = o.output_times[i];
    if (!(ti >= t_begin && ti <= t_end)) {
      fail(fmt::format("output time {} is outside [{}, {}]", ti, t_begin, t_end));
    }
    if (i > 0 && !(ti > o.output_times[i - 1])) {
      fail(fmt::format("output times must increase ({} after {})", ti, o.output_times[i - 1]));
    }
  }
}

// Instants after t_begin (the initial state is always delivered first), the last
// one t_end. An interval's instants are t_begin + k·interval, computed by product
// so that they do not drift; one closer to t_end than 1e-9 intervals merges with it.
Integrator::OutputInstants::OutputInstants(const IntegratorOptions& o, double t_begin, double t_end)
    : t_begin_(t_begin), t_end_(t_end), interval_(o.output_interval) {
  if (interval_ > 0.0) {
    // Instants k = 1 .. K before t_end, K from the ratio then corrected by the test itself.
    const auto inside = [&](double k) {
      return t_begin + k * interval_ < t_end - 1e-9 * interval_;
    };
    double K = std::max(0.0, std::floor((t_end - t_begin) / interval_));
    while (K > 0.0 && !inside(K)) K -= 1.0;
    while (inside(K + 1.0)) K += 1.0;
    count_ = static_cast<std::size_t>(K) + 1;
  } else if (!o.output_times.empty()) {
    times_ = &o.output_times;
    const auto first = std::upper_bound(o.output_times.begin(), o.output_times.end(), t_begin);
    const auto last = std::lower_bound(first, o.output_times.end(), t_end);
    first_ = static_cast<std::size_t>(first - o.output_times.begin());
    count_ = static_cast<std::size_t>(last - first) + 1;
  }
}

double Integrator::OutputInstants::operator[](std::size_t k) const {
  if (k + 1 == count_) return t_end_;
  if (times_ != nullptr) return (*times_)[first_ + k];
  return t_begin_ + static_cast<double>(k + 1) * interval_;
}

State Integrator::integrate(DynamicSystem& system, const State& initial, double t_end) {
  check_options(initial.t, t_end);
  const int n = system.num_coordinates();
  const int m = system.num_extra_states();
  if (initial.q.size() != n || initial.qd.size() != n || initial.y.size() != m) {
    throw ModelError(fmt::format(
        "integrator '{}': the initial state has q ({}), qd ({}), y ({}); the system has {} "
        "coordinates and {} extra states",
        name(), initial.q.size(), initial.qd.size(), initial.y.size(), n, m));
  }
  const std::string bad = detail::non_finite_value(system, initial, Vector(), Vector());
  if (!bad.empty()) throw NumericError(detail::at_time(initial.t, bad + " (initial state)"));
  ErrorWeights(options_, name(), n, m);  // checks q_scale before the run
  if (options_.global_tolerance > 0.0) {
    if (fixed_step_order() > 0) return run_by_step_halving(system, initial, t_end);
    if (options_.fixed_step) {
      throw OptionError(
          fmt::format("integrator '{}': global_tolerance at a fixed step needs the method's order, "
                      "which '{}' does not give: drop fixed_step or global_tolerance",
                      name(), name()));
    }
    return run_to_global_tolerance(system, initial, t_end);
  }
  return run_once(system, initial, t_end);
}

State Integrator::run_once(DynamicSystem& system, const State& initial, double t_end) {
  stats_ = Statistics{};
  stats_.last_relative_tolerance = options_.relative_tolerance;
  t_begin_ = initial.t;
  t_end_ = t_end;
  instants_ = OutputInstants(options_, initial.t, t_end);
  return run(system, initial, t_end);
}

namespace {

struct Output {
  State s;
  Vector qdd, yd;
};

// A run's end and the outputs it delivered.
struct HeldRun {
  State end;
  std::vector<Output> outputs;
};

// What both global-tolerance loops share: the user's options back however the runs end,
// and each run's outputs held (only the accepted run's reach the user, through replay).
struct HeldRuns {
  explicit HeldRuns(IntegratorOptions& options) : options(options), user(options) {
    if (user.on_output) {
      options.on_output = [this](const State& s, const Vector& qdd, const Vector& yd) {
        outputs.push_back({s, qdd, yd});
      };
    }
  }
  ~HeldRuns() { options = user; }
  HeldRuns(const HeldRuns&) = delete;
  HeldRuns& operator=(const HeldRuns&) = delete;

  IntegratorOptions& options;
  const IntegratorOptions user;
  std::vector<Output> outputs, previous_outputs;
};

// The outputs of the run that met the global tolerance, kept while the runs
// were compared, given to the caller.
void replay(const std::vector<Output>& outputs, const IntegratorOptions& user) {
  if (!user.on_output) return;
  for (const Output& o : outputs) user.on_output(o.s, o.qdd, o.yd);
}

constexpr double kTightening = 100.0;  // between two runs: two decades
// The error of every adaptive integrator falls about as its tolerance (a power of 0.79 to
// 1.2 over seven decades on the reference problems, bench/results/global_tolerance.md): a
// tightening by F divides it by about F. An observed fall d_k/d_(k-1) within this factor of
// 1/F is that regime; outside it the error is erratic there, and extrapolating from it fails.
constexpr double kConsistent = 2.0;
// Whether a fall observed is within kConsistent of the one expected (its asymptotic regime:
// a tolerance's, or a step halving's 2^-p).
bool consistent_fall(double observed, double expected) {
  return observed <= kConsistent * expected && observed >= expected / kConsistent;
}
// Runs converge when each difference is at most half the one before.
constexpr double kConverging = 0.5;

// The largest difference of two states in every component: q and qd divided by q_scale.
double difference(const State& a, const State& b, const std::vector<double>& q_scale) {
  double d = (a.y - b.y).lpNorm<Eigen::Infinity>();
  for (Eigen::Index i = 0; i < a.q.size(); ++i) {
    const double s = q_scale.empty() ? 1.0 : q_scale[static_cast<std::size_t>(i)];
    d = std::max({d, std::abs(a.q[i] - b.q[i]) / s, std::abs(a.qd[i] - b.qd[i]) / s});
  }
  return d;
}

// The largest difference between two runs at their final states and, when both
// delivered the same instants, at every output.
double difference(const State& a, const State& b, const std::vector<Output>& oa,
                  const std::vector<Output>& ob, const std::vector<double>& q_scale) {
  double d = difference(a, b, q_scale);
  if (oa.size() != ob.size()) return d;
  for (std::size_t k = 0; k < oa.size(); ++k) {
    if (oa[k].s.t != ob[k].s.t) return difference(a, b, q_scale);
    d = std::max(d, difference(oa[k].s, ob[k].s, q_scale));
  }
  return d;
}

}  // namespace

// Run k at tolerances tol/100^k, but not below tightest_tolerance() (the last
// tightening then smaller, F_k < 100). Runs k-1 and k differ by d_k. Two estimates:
// - run k-1 against run k: its error is d_k within run k's error, which is about d_k/F_k,
//   so d_k/(1 - 1/F_k). Robust (run k is a reference 100 times tighter), but it returns
//   the looser run; from the third run on it needs d_k <= d_(k-1)/2 (the runs converge);
// - run k extrapolated: d_k·r/(1 - r), r its fall, from the third run on and only where
//   the fall observed over the tightening before, d_k/d_(k-1), is within a factor 2 of
//   1/F_(k-1) (the error falls as the tolerance); r = F_k^-a, a the smaller of the observed
//   power and 1 (the larger estimate). Where the fall is erratic (dop853 and cvode over
//   short runs fall 2 to 12 000 times per two decades) this extrapolation is 100 times
//   off either way, and only the first estimate is taken.
// The tighter run is returned when its estimate meets the tolerance, else the looser one
// when its estimate does, else the tolerance is tightened again.
State Integrator::run_to_global_tolerance(DynamicSystem& system, const State& initial,
                                          double t_end) {
  HeldRuns held(options_);
  const IntegratorOptions& user = held.user;
  std::vector<Output>& outputs = held.outputs;
  std::vector<Output>& previous_outputs = held.previous_outputs;
  Statistics total;
  total.runs = 0;
  State previous;
  double previous_difference = 0.0;
  double previous_tolerance = 0.0;
  double scale = 1.0;                // of both tolerances, run k
  double tightening = 1.0;           // F_k
  double previous_tightening = 1.0;  // F_(k-1)
  const auto accept = [&](State& end, const std::vector<Output>& held_outputs, double estimate,
                          double tolerance) {
    total.global_error_estimate = estimate;
    total.last_relative_tolerance = tolerance;
    total.global_tolerance_met = true;
    stats_ = total;
    replay(held_outputs, user);
    return std::move(end);
  };
  for (int k = 0;; ++k) {
    options_.relative_tolerance = user.relative_tolerance * scale;
    options_.absolute_tolerance = user.absolute_tolerance * scale;
    outputs.clear();
    State end;
    try {
      end = run_once(system, initial, t_end);
    } catch (const NumericError& e) {
      if (k == 0) throw;
      stats_ = total;
      const std::string estimate =
          k < 2 ? std::string()
                : fmt::format("; the run at {:g} was estimated {:g} off",
                              total.last_relative_tolerance, total.global_error_estimate);
      throw NumericError(fmt::format(
          "integrator '{}': global_tolerance {:g} not reached: the run at a local "
          "tolerance of {:g} failed{}: {}",
          name(), user.global_tolerance, options_.relative_tolerance, estimate, e.what()));
    }
    total.add_work(stats_);
    ++total.runs;
    const double tolerance = options_.relative_tolerance;
    if (k > 0) {
      const double d = difference(previous, end, previous_outputs, outputs, user.q_scale);
      const double observed = k >= 2 ? d / previous_difference : 0.0;
      const double expected = 1.0 / previous_tightening;
      const bool consistent = k >= 2 && consistent_fall(observed, expected);
      double extrapolated = std::numeric_limits<double>::infinity();
      if (consistent) {
        const double power = std::min(1.0, std::log(observed) / std::log(expected));
        const double fall = std::pow(tightening, -power);
        extrapolated = d * fall / (1.0 - fall);
        if (extrapolated <= user.global_tolerance)
          return accept(end, outputs, extrapolated, tolerance);
      }
      const bool converging = k == 1 || d <= kConverging * previous_difference;
      const double looser = d / (1.0 - 1.0 / tightening);
      if (converging && looser <= user.global_tolerance)
        return accept(previous, previous_outputs, looser, previous_tolerance);
      // Not met: the statistics give the estimate that holds (infinite for none).
      total.global_error_estimate = consistent   ? extrapolated
                                    : converging ? looser
                                                 : std::numeric_limits<double>::infinity();
      total.last_relative_tolerance = consistent ? tolerance : previous_tolerance;
      previous_difference = d;
      previous_tightening = tightening;
    }
    const double tightest =
        tightest_tolerance() / std::max(user.relative_tolerance, user.absolute_tolerance);
    const double next = std::max(scale / kTightening, std::min(scale, tightest));
    if (!(next < scale)) {
      stats_ = total;
      throw NumericError(
          fmt::format("integrator '{}': global_tolerance {:g} not reached: at a local tolerance of "
                      "{:g} the error is "
                      "estimated at {:g} (the last two runs differ by {:g})",
                      name(), user.global_tolerance, total.last_relative_tolerance,
                      total.global_error_estimate, previous_difference));
    }
    tightening = scale / next;
    scale = next;
    previous_tolerance = tolerance;
    previous = std::move(end);
    std::swap(outputs, previous_outputs);
  }
}

namespace {

// x_h + (x_h - x_2h)·c at the end and at every output: Richardson's extrapolation of two
// runs at steps 2h and h. Empty when the runs' outputs are not at the same instants.
std::optional<HeldRun> extrapolate(const State& coarse, const State& fine,
                                   const std::vector<Output>& coarse_outputs,
                                   const std::vector<Output>& fine_outputs, double c) {
  if (coarse_outputs.size() != fine_outputs.size()) return std::nullopt;
  const auto combine = [c](const Vector& a, const Vector& b) -> Vector { return b + c * (b - a); };
  const auto state = [&](const State& a, const State& b) {
    return State{b.t, combine(a.q, b.q), combine(a.qd, b.qd), combine(a.y, b.y)};
  };
  HeldRun r{state(coarse, fine), {}};
  r.outputs.reserve(fine_outputs.size());
  for (std::size_t k = 0; k < fine_outputs.size(); ++k) {
    const Output &a = coarse_outputs[k], &b = fine_outputs[k];
    if (a.s.t != b.s.t) return std::nullopt;
    r.outputs.push_back({state(a.s, b.s), combine(a.qdd, b.qdd), combine(a.yd, b.yd)});
  }
  return r;
}

// The rounding a run of `steps` steps may accumulate: 10 roundings per step (an
// implicit step's equations are solved to about that) of its end's largest component
// (q and qd over q_scale, y).
double rounding_floor(long steps, const State& end, const std::vector<double>& q_scale) {
  const State zero{end.t, Vector::Zero(end.q.size()), Vector::Zero(end.qd.size()),
                   Vector::Zero(end.y.size())};
  return 10.0 * std::numeric_limits<double>::epsilon() * static_cast<double>(steps) *
         difference(end, zero, q_scale);
}

}  // namespace

// Run k at the step h/2^k. The difference d_k of runs k-1 and k is the error of
// run k-1 less that of run k; with the error C·h^p, run k's is d_k/(2^p - 1)
// (Richardson). Where the error does not yet fall as h^p (a step too long for the
// asymptotic regime, an interpolated output of lower order than the method), the
// fall r_k = d_k/d_(k-1) observed is slower than 2^-p, and run k's error is
// d_k·r_k/(1 - r_k) as for a geometric series: the larger of the two is the
// estimate, so a run is accepted from the third one on, when r_k is known. A fall
// slower than 3/4 per halving is no convergence: halve again.
// Runs k-1 and k extrapolated, e_k = x_k + d_k/(2^p - 1), are of order p + g (g = 2
// for a symmetric method, else 1). From the fourth run on, where r_k is within a
// factor 2 of 2^-p and the fall rho_k = |e_k - e_(k-1)|/|e_(k-1) - e_(k-2)| within a
// factor 2 of 2^-(p+g) (both in their asymptotic range), e_k's error is
// |e_k - e_(k-1)|·max(1/(2^(p+g) - 1), rho_k/(1 - rho_k)), and e_k is returned
// when that estimate is the smaller and meets the tolerance. The runs' implicit equations are
// solved at a tolerance of kSolveTo (to rounding), so that their error falls with h like the
// method's. No estimate is below the rounding a run accumulates (rounding_floor),
// which grows as the step halves: the runs stop when it alone is above the tolerance.
State Integrator::run_by_step_halving(DynamicSystem& system, const State& initial, double t_end) {
  constexpr int kMaxHalvings = 12;
  constexpr double kSlowestFall = 0.75;
  constexpr double kSolveTo = 1e-13;
  HeldRuns held(options_);
  const IntegratorOptions& user = held.user;
  std::vector<Output>& outputs = held.outputs;
  std::vector<Output>& previous_outputs = held.previous_outputs;
  const int p = fixed_step_order();
  const double richardson = 1.0 / (std::pow(2.0, p) - 1.0);
  const int gain = fixed_step_symmetric() ? 2 : 1;  // orders an extrapolation gains
  const double extrapolated_richardson = 1.0 / (std::pow(2.0, p + gain) - 1.0);
  options_.relative_tolerance = std::min(user.relative_tolerance, kSolveTo);
  options_.absolute_tolerance = std::min(user.absolute_tolerance, kSolveTo);
  Statistics total;
  total.runs = 0;
  State previous;
  std::optional<HeldRun> previous_extrapolated;
  double previous_difference = 0.0;
  const auto not_reached = [&](const std::string& why) {
    stats_ = total;
    const std::string reached =
        total.runs >= 3
            ? fmt::format("the result at a step of {:g} s{} is estimated {:g} off", total.last_step,
                          total.extrapolated ? " (extrapolated)" : "", total.global_error_estimate)
            : fmt::format("{} run(s), down to a step of {:g} s, too few for an estimate",
                          total.runs, total.last_step);
    return NumericError(
        fmt::format("integrator '{}': global_tolerance {:g} not reached by step halving from "
                    "initial_step {:g} ({}): {}",
                    name(), user.global_tolerance, user.initial_step, why, reached));
  };
  const auto accept = [&](State& end, const std::vector<Output>& held_outputs, double estimate) {
    total.global_error_estimate = estimate;
    total.global_tolerance_met = true;
    stats_ = total;
    replay(held_outputs, user);
    return std::move(end);
  };
  // e_k's error where runs k-1, k and e_(k-1), e_k both fall as they should (the runs'
  // differences as h^p, the extrapolations' as h^(p+g), each within a factor 2), from the
  // fall rho of the extrapolations as for the runs; else infinite (none).
  double previous_extrapolated_difference = 0.0;
  const auto extrapolated_estimate = [&](double fall, const std::optional<HeldRun>& e,
                                         double floor) {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (!e || !previous_extrapolated) {
      previous_extrapolated_difference = 0.0;
      return kNone;
    }
    const double d = difference(previous_extrapolated->end, e->end, previous_extrapolated->outputs,
                                e->outputs, user.q_scale);
    const double d_previous = std::exchange(previous_extrapolated_difference, d);
    if (!(d_previous > 0.0) || !consistent_fall(fall, std::ldexp(1.0, -p))) return kNone;
    const double rho = d / d_previous;
    if (!consistent_fall(rho, std::ldexp(1.0, -(p + gain)))) return kNone;
    return std::max(floor, d * std::max(extrapolated_richardson, rho / (1.0 - rho)));
  };
  for (int k = 0;; ++k) {
    options_.initial_step = std::ldexp(user.initial_step, -k);
    if (k > 0 && options_.initial_step < user.min_step) {
      throw not_reached(fmt::format("the next step {:g} s is below min_step {:g}",
                                    options_.initial_step, user.min_step));
    }
    if (k > 0 &&
        (t_end - initial.t) / options_.initial_step > static_cast<double>(user.max_steps)) {
      throw not_reached(fmt::format("a step of {:g} s would take more than max_steps {}",
                                    options_.initial_step, user.max_steps));
    }
    outputs.clear();
    State end;
    try {
      end = run_once(system, initial, t_end);
    } catch (const NumericError& e) {
      if (k == 0) throw;
      throw not_reached(
          fmt::format("the run at a step of {:g} s failed: {}", options_.initial_step, e.what()));
    }
    total.add_work(stats_);
    ++total.runs;
    total.last_step = options_.initial_step;
    total.last_relative_tolerance = options_.relative_tolerance;
    total.extrapolated = false;
    if (k > 0) {
      const double d = difference(previous, end, previous_outputs, outputs, user.q_scale);
      std::optional<HeldRun> extrapolated =
          extrapolate(previous, end, previous_outputs, outputs, richardson);
      if (k >= 2) {
        const double floor = rounding_floor(stats_.steps, end, user.q_scale);
        const double fall =
            previous_difference > 0.0 ? d / previous_difference : (d > 0.0 ? 1.0 : 0.0);
        const double plain = fall < kSlowestFall
                                 ? std::max(floor, d * std::max(richardson, fall / (1.0 - fall)))
                                 : std::numeric_limits<double>::infinity();
        const double of_extrapolated = extrapolated_estimate(fall, extrapolated, floor);
        total.extrapolated = of_extrapolated < plain;
        total.global_error_estimate = std::min(plain, of_extrapolated);
        if (total.global_error_estimate <= user.global_tolerance) {
          return total.extrapolated
                     ? accept(extrapolated->end, extrapolated->outputs, of_extrapolated)
                     : accept(end, outputs, plain);
        }
        if (floor > user.global_tolerance) {
          throw not_reached(fmt::format("the rounding of its {} steps, up to {:g}, is above it",
                                        stats_.steps, floor));
        }
      }
      previous_difference = d;
      previous_extrapolated = std::move(extrapolated);
    }
    if (k == kMaxHalvings) throw not_reached(fmt::format("{} halvings", kMaxHalvings));
    previous = std::move(end);
    std::swap(outputs, previous_outputs);
  }
}

void Integrator::emit(DynamicSystem& system, const State& s, const Vector& qdd, const Vector& yd) {
  const std::string bad = detail::non_finite_value(system, s, qdd, yd);
  if (!bad.empty()) throw NumericError(detail::at_time(s.t, bad));
  if (options_.on_output) options_.on_output(s, qdd, yd);
}

void Integrator::progress(double t) const {
  if (options_.on_progress) options_.on_progress(t, t_begin_, t_end_);
}

ErrorWeights::ErrorWeights(const IntegratorOptions& options, std::string_view integrator, int n,
                           int m)
    : atol_(options.absolute_tolerance),
      rtol_(options.relative_tolerance),
      n_(n),
      m_(m),
      w_(Vector::Constant(2 * n + m, options.absolute_tolerance + options.relative_tolerance)) {
  const auto& scale = options.q_scale;
  if (scale.empty()) return;
  if (static_cast<int>(scale.size()) != n) {
    throw OptionError(
        fmt::format("integrator '{}': q_scale has {} entries, the system has {} coordinates",
                    integrator, scale.size(), n));
  }
  for (int i = 0; i < n; ++i) {
    const double s = scale[static_cast<std::size_t>(i)];
    if (!(std::isfinite(s) && s > 0.0)) {
      throw OptionError(fmt::format("integrator '{}': q_scale[{}] = {} must be finite and positive",
                                    integrator, i, s));
    }
    w_[i] = atol_ + rtol_ * s;
  }
}

const Vector& ErrorWeights::update(const Vector& x0, const Vector& x1) {
  for (int i = n_; i < 2 * n_ + m_; ++i) {
    w_[i] = atol_ + rtol_ * std::max(std::abs(x0[i]), std::abs(x1[i]));
  }
  return w_;
}

const Vector& ErrorWeights::update(const State& s0, const State& s1) {
  for (int i = 0; i < n_; ++i) {
    w_[n_ + i] = atol_ + rtol_ * std::max(std::abs(s0.qd[i]), std::abs(s1.qd[i]));
  }
  for (int j = 0; j < m_; ++j) {
    w_[2 * n_ + j] = atol_ + rtol_ * std::max(std::abs(s0.y[j]), std::abs(s1.y[j]));
  }
  return w_;
}

double ErrorWeights::rms(const Vector& e) const {
  const double mean =
      e.cwiseQuotient(w_).squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, w_.size()));
  return std::sqrt(mean);
}

}  // namespace symdyn::runtime
