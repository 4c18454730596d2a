#include "runtime/cvode_integrator.hpp"

#include <cmath>
#include <cstdlib>
#include <exception>

#include <cvode/cvode.h>
#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "runtime/errors.hpp"
#include "runtime/stepping_integrator.hpp"

namespace symdyn::runtime {

namespace {

// What the C callbacks see (user data): the system, scratch, and what went wrong.
struct CallbackData {
  DynamicSystem* system = nullptr;
  int n = 0;
  int m = 0;
  State s;
  Vector qdd, yd;
  long evaluations = 0;
  std::string last_failure;     // last non-finite value or NumericError, with its time
  std::string cvode_message;    // CVODE's own message of its last error
  std::exception_ptr error;     // any other exception, rethrown after CVODE returns
};

// Unpacks x = (q, qd, y) into data.s at t.
void unpack(CallbackData& d, double t, N_Vector x) {
  const Eigen::Map<const Vector> xv(N_VGetArrayPointer(x), 2 * d.n + d.m);
  d.s.t = t;
  d.s.q = xv.head(d.n);
  d.s.qd = xv.segment(d.n, d.n);
  d.s.y = xv.tail(d.m);
}

// dx = (qd, qdd, yd). Returns 0, 1 (recoverable: CVODE retries with a smaller step)
// or -1 (unrecoverable: the exception is kept and rethrown).
int right_hand_side(realtype t, N_Vector x, N_Vector dx, void* user) {
  auto& d = *static_cast<CallbackData*>(user);
  try {
    unpack(d, t, x);
    ++d.evaluations;
    d.qdd.resize(d.n);
    d.yd.resize(d.m);
    d.system->accelerations(d.s, d.qdd, d.yd);
    const std::string bad = detail::non_finite_value(*d.system, d.s, d.qdd, d.yd);
    if (!bad.empty()) {
      d.last_failure = detail::at_time(t, bad);
      return 1;
    }
    Eigen::Map<Vector> out(N_VGetArrayPointer(dx), 2 * d.n + d.m);
    out << d.s.qd, d.qdd, d.yd;
    return 0;
  } catch (const NumericError& e) {
    d.last_failure = detail::at_time(t, e.what());
    return 1;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

void keep_message(int, const char*, const char* function, char* message, void* user) {
  static_cast<CallbackData*>(user)->cvode_message = fmt::format("{}: {}", function, message);
}

// Owns the SUNDIALS objects of one run.
struct Sundials {
  SUNContext context = nullptr;
  N_Vector x = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver solver = nullptr;
  void* cvode = nullptr;

  Sundials() = default;
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  ~Sundials() {
    if (cvode != nullptr) CVodeFree(&cvode);
    if (solver != nullptr) SUNLinSolFree(solver);
    if (A != nullptr) SUNMatDestroy(A);
    if (x != nullptr) N_VDestroy(x);
    if (context != nullptr) SUNContext_Free(&context);
  }
};

class Cvode final : public Integrator {
 public:
  using Integrator::Integrator;
  std::string_view name() const override { return "cvode"; }

 private:
  State run(DynamicSystem& system, const State& initial, double t_end) override;
  void setup(Sundials& sun, CallbackData& data, const State& initial, double t_end);
  void deliver(CallbackData& data, double t, N_Vector x);
  void collect_statistics(const Sundials& sun, const CallbackData& data);
};

// CVODE's name of a return flag (CVodeGetReturnFlagName allocates it with malloc).
std::string flag_name(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string copy = name != nullptr ? name : fmt::format("flag {}", flag);
  std::free(name);
  return copy;
}

// Throws NumericError for a negative SUNDIALS flag, naming the call.
void check(int flag, const char* call, const CallbackData& data) {
  if (flag >= 0) return;
  throw NumericError(fmt::format("integrator 'cvode': {} failed with {} ({})", call,
                                 flag_name(flag), data.cvode_message));
}

void Cvode::setup(Sundials& sun, CallbackData& data, const State& initial, double t_end) {
  const int size = 2 * data.n + data.m;
  if (SUNContext_Create(nullptr, &sun.context) != 0) {
    throw NumericError("integrator 'cvode': SUNContext_Create failed");
  }
  sun.x = N_VNew_Serial(size, sun.context);
  sun.A = SUNDenseMatrix(size, size, sun.context);
  sun.cvode = CVodeCreate(CV_BDF, sun.context);
  if (sun.x == nullptr || sun.A == nullptr || sun.cvode == nullptr) {
    throw NumericError("integrator 'cvode': out of memory creating CVODE");
  }
  sun.solver = SUNLinSol_Dense(sun.x, sun.A, sun.context);
  Eigen::Map<Vector>(N_VGetArrayPointer(sun.x), size) << initial.q, initial.qd, initial.y;

  void* mem = sun.cvode;
  check(CVodeSetErrHandlerFn(mem, keep_message, &data), "CVodeSetErrHandlerFn", data);
  check(CVodeInit(mem, right_hand_side, initial.t, sun.x), "CVodeInit", data);
  check(CVodeSetUserData(mem, &data), "CVodeSetUserData", data);
  check(CVodeSStolerances(mem, options_.relative_tolerance, options_.absolute_tolerance),
        "CVodeSStolerances", data);
  check(CVodeSetLinearSolver(mem, sun.solver, sun.A), "CVodeSetLinearSolver", data);
  check(CVodeSetMaxNumSteps(mem, 1000000000L), "CVodeSetMaxNumSteps", data);
  check(CVodeSetStopTime(mem, t_end), "CVodeSetStopTime", data);
  check(CVodeSetMinStep(mem, options_.min_step), "CVodeSetMinStep", data);
  if (std::isfinite(options_.max_step)) {
    check(CVodeSetMaxStep(mem, options_.max_step), "CVodeSetMaxStep", data);
  }
  if (options_.initial_step > 0.0) {
    check(CVodeSetInitStep(mem, options_.initial_step), "CVodeSetInitStep", data);
  }
}

// One output: the state at t with qdd and yd evaluated there.
void Cvode::deliver(CallbackData& data, double t, N_Vector x) {
  unpack(data, t, x);
  ++data.evaluations;
  data.qdd.resize(data.n);
  data.yd.resize(data.m);
  data.system->accelerations(data.s, data.qdd, data.yd);
  emit(*data.system, data.s, data.qdd, data.yd);
  progress(t);
}

void Cvode::collect_statistics(const Sundials& sun, const CallbackData& data) {
  long steps = 0, test_failures = 0, convergence_failures = 0, jacobians = 0, iterations = 0;
  CVodeGetNumSteps(sun.cvode, &steps);
  CVodeGetNumErrTestFails(sun.cvode, &test_failures);
  CVodeGetNumNonlinSolvConvFails(sun.cvode, &convergence_failures);
  CVodeGetNumJacEvals(sun.cvode, &jacobians);
  CVodeGetNumNonlinSolvIters(sun.cvode, &iterations);
  stats_.steps = steps;
  stats_.rejected_steps = test_failures + convergence_failures;
  stats_.jacobian_evaluations = jacobians;
  stats_.newton_iterations = iterations;
  stats_.rhs_evaluations = data.evaluations;
}

State Cvode::run(DynamicSystem& system, const State& initial, double t_end) {
  if (options_.fixed_step) {
    throw OptionError("integrator 'cvode': fixed_step is not available (CVODE is adaptive)");
  }
  CallbackData data;
  data.system = &system;
  data.n = system.num_coordinates();
  data.m = system.num_extra_states();
  if (2 * data.n + data.m == 0) throw ModelError("integrator 'cvode': the system has no state");
  Sundials sun;
  setup(sun, data, initial, t_end);

  // The initial output, through the same path as the others.
  deliver(data, initial.t, sun.x);

  // Advances to `target` (CV_NORMAL) or by one step (CV_ONE_STEP), reporting failures.
  auto advance = [&](double target, int mode) {
    double reached = initial.t;
    const int flag = CVode(sun.cvode, target, sun.x, &reached, mode);
    collect_statistics(sun, data);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      CVodeGetCurrentTime(sun.cvode, &reached);
      throw NumericError(detail::at_time(
          reached, fmt::format("integrator 'cvode' failed with {} ({}){}",
                               flag_name(flag), data.cvode_message,
                               data.last_failure.empty() ? "" : "; last failure: " + data.last_failure)));
    }
    return reached;
  };
  double t = initial.t;
  if (output_every_step()) {
    while (t < t_end) {
      t = advance(t_end, CV_ONE_STEP);
      deliver(data, t, sun.x);
    }
  } else {
    for (double target : output_instants()) {
      t = advance(target, CV_NORMAL);
      deliver(data, target, sun.x);
    }
  }
  collect_statistics(sun, data);
  unpack(data, t_end, sun.x);
  return data.s;
}

}  // namespace

std::unique_ptr<Integrator> make_cvode(IntegratorOptions options) {
  return std::make_unique<Cvode>(std::move(options));
}

}  // namespace symdyn::runtime
