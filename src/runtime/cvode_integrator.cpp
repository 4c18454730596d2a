#include "runtime/cvode_integrator.hpp"

#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>
#include <type_traits>

#include <cvode/cvode.h>
#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "runtime/errors.hpp"
#include "runtime/stepping_integrator.hpp"
#include "runtime/sundials_support.hpp"

namespace symdyn::runtime {

namespace {

using detail::CallbackData;
using detail::error_weights;
using detail::keep_message;
using detail::right_hand_side;
using detail::unpack;

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
                                 flag_name(flag), data.solver_message));
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
  check(CVodeWFtolerances(mem, error_weights), "CVodeWFtolerances", data);
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
  ErrorWeights weights(options_, name(), data.n, data.m);
  data.weights = &weights;
  Sundials sun;
  setup(sun, data, initial, t_end);

  // The initial output, through the same path as the others.
  deliver(data, initial.t, sun.x);

  // Advances by one step towards `target`, reporting failures.
  auto advance = [&](double target, int mode) {
    double reached = initial.t;
    const int flag = CVode(sun.cvode, target, sun.x, &reached, mode);
    collect_statistics(sun, data);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      CVodeGetCurrentTime(sun.cvode, &reached);
      throw NumericError(detail::at_time(
          reached, fmt::format("integrator 'cvode' failed with {} ({}){}",
                               flag_name(flag), data.solver_message,
                               data.last_failure.empty() ? "" : "; last failure: " + data.last_failure)));
    }
    return reached;
  };
  // One step at a time (CV_ONE_STEP, never past t_end), the output instants in each
  // step from CVODE's interpolating polynomial: the outputs do not change the steps.
  N_Vector at = N_VClone(sun.x);
  const std::unique_ptr<std::remove_pointer_t<N_Vector>, void (*)(N_Vector)> owner(at, N_VDestroy);
  std::size_t next_output = 0;
  double t = initial.t;
  while (t < t_end) {
    t = advance(t_end, CV_ONE_STEP);
    if (output_every_step()) {
      deliver(data, t, sun.x);
      continue;
    }
    for (; next_output < output_instants().size() && output_instants()[next_output] <= t; ++next_output) {
      const double ti = output_instants()[next_output];
      check(CVodeGetDky(sun.cvode, ti, 0, at), "CVodeGetDky", data);
      deliver(data, ti, at);
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
