#pragma once
// One interface for every time integrator of the runtime.
//
//   auto integ = make_integrator("newmark", options);
//   State end = integ->integrate(system, initial, t_end);
//   integ->statistics().steps ...
//
// The integrators, by name (make_integrator):
//
//   "newmark"            EasyDyn's scheme: Newmark beta = 1/4, gamma = 1/2 (average
//                        acceleration, no numerical damping) with Newton iterations on
//                        the residual; implicit, second order, A-stable.
//   "generalized-alpha"  Chung-Hulbert's generalized-alpha (parameters from
//                        rho_infinity) in Arnold-Bruls' form: the residual holds at
//                        the step end; implicit, second order, damps high frequencies.
//   "rk4"                classic fixed-step Runge-Kutta 4 on the first-order form.
//   "dopri5"             Dormand-Prince 5(4), adaptive, with dense output.
//   "dop853"             Dormand-Prince 8(5,3), adaptive, with a seventh-order dense
//                        output: for tight tolerances and reference solutions.
//   "midpoint"           implicit midpoint on Hamilton's equations in (q, p = M·qd),
//                        fixed step, symplectic, second order: bounded energy error
//                        over long runs of conservative mechanisms.
//   "cvode"              SUNDIALS CVODE, BDF orders 1-5 with Newton and a dense
//                        linear solver (difference-quotient Jacobian): the reference
//                        stiff solver.
//   "arkode"             SUNDIALS ARKODE ARKStep, the fourth-order L-stable SDIRK-5-3-4
//                        with Newton and a dense linear solver: a one-step stiff solver.
//
// All of them integrate the n coordinates q (second order) and the m extra states y
// (first order) of a DynamicSystem together. "newmark" and "generalized-alpha" use
// the residual form and DynamicSystem::jacobians; "midpoint" the residual (for M)
// and the accelerations; the others the explicit form DynamicSystem::accelerations
// on x = (q, qd, y).
//
// Error control: every adaptive integrator measures its local error estimate e of
// x = (q, qd, y) with the same weights (ErrorWeights below),
//
//   w_i = absolute_tolerance + relative_tolerance·s_i,   accepted when
//   sqrt(mean_i (e_i / w_i)²) <= 1,
//
//   s_i = q_scale[i] (1 unless set) for a coordinate q_i: a fixed scale, never |q_i|,
//         since a crank that has wound up 3 900 rad is not known less precisely;
//   s_i = max(|x_i(t0)|, |x_i(t1)|) for a rate qd_i or an extra state y_i (both ends
//         of the step; cvode and arkode see the current value only).
//
// Output instants: a list of times, or a fixed interval from the initial time, or
// (both empty) every accepted step. The initial and final states are always
// delivered. The output instants never change the steps taken: every integrator
// interpolates between accepted steps (dense output) and only the last step is
// shortened, to end at t_end. newmark, generalized-alpha, rk4 and midpoint use the
// quintic Hermite interpolant of q from (q, qd, qdd) at both ends of the step (cubic
// ones for qdd from (qd, qdd) and for y from (y, yd)), dopri5 and dop853 their
// continuous extensions (orders 4 and 7), cvode and arkode their own interpolating
// polynomials.
//
// Errors (errors.hpp), each naming the time and the culprit:
//   OptionError   bad options (tolerances <= 0, min_step > max_step, rk4 or midpoint without
//                 initial_step, output times outside the interval, unknown name);
//   ModelError    state sizes that do not match the system;
//   NumericError  a value that is not finite (q, qd, y, qdd, yd or a residual, with
//                 the coordinate or extra state named), a step size below min_step,
//                 a Newton iteration that fails at a fixed step, a CVODE failure.
// Adaptive methods treat a non-finite value or a failed Newton iteration as a
// rejected step (the step is divided by 4, as in EasyDyn) and report it only when
// the step size falls below min_step. Every output instant reached before an error
// has already been delivered to the output callback when the exception is thrown.

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

// Called at each output instant with the state, qdd (n) and yd (m) at that instant.
using OutputCallback = std::function<void(const State& s, const Vector& qdd, const Vector& yd)>;

// Called after each accepted step (or each output for cvode): current time, and the
// interval of the run. Draw a progress bar with it (see progress_bar.hpp).
using ProgressCallback = std::function<void(double t, double t_begin, double t_end)>;

struct IntegratorOptions {
  // The error test (see ErrorWeights): |e_i| <= absolute + relative·s_i, as a root
  // mean square over the components of x = (q, qd, y); newmark, generalized-alpha and
  // cvode hold each step within a power of the relative tolerance of it (sqrt, cube
  // root: their errors add up over a run, newmark.hpp, cvode_integrator.hpp).
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 1e-8;
  // (n or empty) the scale s_i of coordinate q_i in the error test, each > 0 (a
  // length in m, an angle in rad); empty: 1 for every coordinate.
  std::vector<double> q_scale;

  // 0 (default): the tolerances above bound each step's error, not the error at
  // t_end, which grows with the number of steps and, in a mechanism whose period
  // depends on its energy, with time; the run has no estimate of its global error.
  // > 0: a bound on the error of the result in every component (|Δq_i| and |Δqd_i|
  // divided by q_scale[i], |Δy_j|; at t_end and at each fixed output instant),
  // estimated by solving again (docs/integrators.md, "The error at t_end"):
  // - adaptive runs are repeated with both tolerances divided by 100, a run's error
  //   estimated against the next, tighter one (or, where the error is seen to fall as
  //   the tolerance, extrapolated for the last run), and the looser run of the last
  //   two returned when only its estimate meets the tolerance,
  // - fixed-step runs (rk4, midpoint, fixed_step) with the step halved, the error
  //   of the finer run estimated by Richardson, |x_h - x_h/2| / (2^p - 1) for a
  //   method of order p (or the fall observed between runs when slower), from the
  //   third run on; where the runs are in their asymptotic range, the last two
  //   extrapolated (x_h/2 + (x_h/2 - x_h)/(2^p - 1), of order p + 2 for a symmetric
  //   method, p + 1 otherwise) and returned when that has the smaller estimate
  //   (Statistics::extrapolated),
  // until the estimated error of a run is below it. Costs 2 or more runs (3
  // or more at a fixed step); outputs are held and only the returned run's are
  // delivered. A NumericError naming the estimate reached when a local tolerance
  // of 1e-14, 12 halvings, min_step or max_steps do not get there or a run fails;
  // an OptionError before the run for a fixed step of unknown order (arkode).
  double global_tolerance = 0.0;

  double initial_step = 0.0;  // 0: the integrator chooses (rk4 requires it > 0)
  double min_step = 1e-12;    // below it (a fixed step too), a run stops with an error
  double max_step = std::numeric_limits<double>::infinity();
  // Step attempts (accepted and rejected) a run may take before it stops with a
  // NumericError; a fixed-step run that would need more is an OptionError at once.
  long max_steps = 100'000'000;

  // newmark, generalized-alpha, dopri5 and dop853: take steps of exactly
  // initial_step (the last one shortened to end at t_end), without error control.
  // For order studies and for users who want EasyDyn's fixed-step mode. rk4 and
  // midpoint always do (they require initial_step > 0).
  bool fixed_step = false;

  // generalized-alpha: spectral radius at infinite frequency, in [0, 1];
  // 1 is Newmark's trapezoidal rule, 0 annihilates the highest frequencies.
  double rho_infinity = 0.8;

  // newmark, generalized-alpha: Newton iterations per step attempt (EasyDyn: 100);
  // midpoint: fixed-point iterations per step.
  int max_newton_iterations = 100;

  // Output instants: either a sorted list (each in [t_begin, t_end]) or an interval
  // (instants t_begin + k·interval). Both empty: every accepted step.
  std::vector<double> output_times;
  double output_interval = 0.0;

  OutputCallback on_output;      // may be empty
  ProgressCallback on_progress;  // may be empty
};

// Counters of the last run (reset by integrate).
struct Statistics {
  long steps = 0;                 // accepted steps
  long rejected_steps = 0;        // error test, Newton or non-finite failures
  long rhs_evaluations = 0;       // DynamicSystem::accelerations calls
  long residual_evaluations = 0;  // DynamicSystem::residual calls by the integrator
  long jacobian_evaluations = 0;  // iteration matrices evaluated (jacobians, or CVODE's)
  long newton_iterations = 0;     // linear solves with the iteration matrix
  // With global_tolerance: the runs made (their work summed above), the local
  // tolerance of the run returned (and its step, at a fixed step; when it throws, of
  // the run whose estimate is given) and the estimated error of its result, whether
  // below global_tolerance (a run that returns has met it; one that throws has not). Without: one
  // run, the estimate NaN (none).
  int runs = 1;
  double last_relative_tolerance = 0.0;
  double last_step = 0.0;  // fixed-step runs only
  double global_error_estimate = std::numeric_limits<double>::quiet_NaN();
  bool global_tolerance_met = false;
  // Fixed-step runs with global_tolerance: the result is the Richardson extrapolation
  // of the last two runs (steps 2·last_step and last_step), not the last run itself.
  bool extrapolated = false;

  // Adds other's work (the counters above runs) to this one's.
  void add_work(const Statistics& other) {
    steps += other.steps;
    rejected_steps += other.rejected_steps;
    rhs_evaluations += other.rhs_evaluations;
    residual_evaluations += other.residual_evaluations;
    jacobian_evaluations += other.jacobian_evaluations;
    newton_iterations += other.newton_iterations;
  }
};

class Integrator {
 public:
  explicit Integrator(IntegratorOptions options);
  virtual ~Integrator() = default;
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  // The name make_integrator knows it by.
  virtual std::string_view name() const = 0;

  // Integrates from initial (initial.t, q (n), qd (n), y (m)) to t_end > initial.t and
  // returns the final state. Throws OptionError, ModelError, NumericError (see above).
  State integrate(DynamicSystem& system, const State& initial, double t_end);

  const Statistics& statistics() const { return stats_; }
  const IntegratorOptions& options() const { return options_; }
  IntegratorOptions& options() { return options_; }

 protected:
  // The run itself, after the checks: deliver outputs through emit(), count in stats_.
  virtual State run(DynamicSystem& system, const State& initial, double t_end) = 0;

  // Output instants of the run in increasing order, the last one t_end, each
  // computed when asked (a run of 10^9 outputs holds none in memory); empty for
  // "every accepted step" (then t_end is delivered by the run itself).
  class OutputInstants {
   public:
    OutputInstants() = default;
    OutputInstants(const IntegratorOptions& o, double t_begin, double t_end);
    std::size_t size() const { return count_; }
    bool empty() const { return count_ == 0; }
    double operator[](std::size_t k) const;

   private:
    const std::vector<double>* times_ = nullptr;  // the instants of a list, inside (t_begin, t_end)
    std::size_t first_ = 0;                       // index of the first of them in the list
    double t_begin_ = 0.0, t_end_ = 0.0, interval_ = 0.0;
    std::size_t count_ = 0;
  };
  const OutputInstants& output_instants() const { return instants_; }
  bool output_every_step() const { return instants_.empty(); }

  // The relative tolerance below which a run gets no more accurate: global_tolerance
  // tightens no further (1e-14, where rounding takes over, unless the method says otherwise).
  virtual double tightest_tolerance() const { return 1e-14; }

  // The order p of this run's global error in its fixed step h (error ~ h^p); 0 when
  // the run adapts its steps, or takes fixed steps of an order it does not know.
  virtual int fixed_step_order() const { return 0; }
  // Whether that error has an expansion in even powers of h only (a symmetric method:
  // newmark's trapezoidal rule, midpoint): one Richardson extrapolation gains two orders.
  virtual bool fixed_step_symmetric() const { return false; }

  // Delivers one output after checking every value is finite.
  void emit(DynamicSystem& system, const State& s, const Vector& qdd, const Vector& yd);
  void progress(double t) const;

  IntegratorOptions options_;
  Statistics stats_;

 private:
  void check_options(double t_begin, double t_end) const;
  State run_once(DynamicSystem& system, const State& initial, double t_end);
  State run_to_global_tolerance(DynamicSystem& system, const State& initial, double t_end);
  State run_by_step_halving(DynamicSystem& system, const State& initial, double t_end);

  OutputInstants instants_;
  double t_begin_ = 0.0;
  double t_end_ = 0.0;
};

// The weights of the error test, shared by every adaptive integrator (see the top
// of this file). x = (q, qd, y) (2n + m).
class ErrorWeights {
 public:
  // Throws OptionError naming the integrator when q_scale has neither 0 nor n
  // entries or an entry that is not finite and positive.
  ErrorWeights(const IntegratorOptions& options, std::string_view integrator, int n, int m);

  // The weights for a step from x0 to x1 (2n + m each).
  const Vector& update(const Vector& x0, const Vector& x1);
  const Vector& update(const State& s0, const State& s1);

  // sqrt(mean_i (e_i / w_i)²) with the weights of the last update; e (2n + m).
  double rms(const Vector& e) const;
  const Vector& weights() const { return w_; }

 private:
  double atol_, rtol_;
  int n_, m_;
  Vector w_;  // (2n + m); its q part is fixed
};

// The integrator called `name` (see the list above). Throws OptionError naming the
// valid names for an unknown one.
std::unique_ptr<Integrator> make_integrator(std::string_view name, IntegratorOptions options = {});

// The names make_integrator accepts, in the order of the list above.
std::vector<std::string> integrator_names();

}  // namespace symdyn::runtime
