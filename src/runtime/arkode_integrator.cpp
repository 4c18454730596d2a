#include "runtime/arkode_integrator.hpp"

#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>
#include <type_traits>

#include <arkode/arkode_arkstep.h>
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
  void* arkode = nullptr;

  Sundials() = default;
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  ~Sundials() {
    if (arkode != nullptr) ARKStepFree(&arkode);
    if (solver != nullptr) SUNLinSolFree(solver);
    if (A != nullptr) SUNMatDestroy(A);
    if (x != nullptr) N_VDestroy(x);
    if (context != nullptr) SUNContext_Free(&context);
  }
};

class Arkode final : public Integrator {
 public:
  using Integrator::Integrator;
  std::string_view name() const override { return "arkode"; }

 private:
  State run(DynamicSystem& system, const State& initial, double t_end) override;
  void setup(Sundials& sun, CallbackData& data, const State& initial, double t_end);
  void deliver(CallbackData& data, double t, N_Vector x);
  void collect_statistics(const Sundials& sun, const CallbackData& data);
};

// ARKODE's name of a return flag (ARKStepGetReturnFlagName allocates it with malloc).
std::string flag_name(int flag) {
  char* name = ARKStepGetReturnFlagName(flag);
  std::string copy = name != nullptr ? name : fmt::format("flag {}", flag);
  std::free(name);
  return copy;
}

// Throws NumericError for a negative SUNDIALS flag, naming the call.
void check(int flag, const char* call, const CallbackData& data) {
  if (flag >= 0) return;
  throw NumericError(fmt::format("integrator 'arkode': {} failed with {} ({})", call,
                                 flag_name(flag), data.solver_message));
}

void Arkode::setup(Sundials& sun, CallbackData& data, const State& initial, double t_end) {
  const int size = 2 * data.n + data.m;
  if (SUNContext_Create(nullptr, &sun.context) != 0) {
    throw NumericError("integrator 'arkode': SUNContext_Create failed");
  }
  sun.x = N_VNew_Serial(size, sun.context);
  sun.A = SUNDenseMatrix(size, size, sun.context);
  if (sun.x == nullptr || sun.A == nullptr) {
    throw NumericError("integrator 'arkode': out of memory creating ARKODE");
  }
  Eigen::Map<Vector>(N_VGetArrayPointer(sun.x), size) << initial.q, initial.qd, initial.y;
  // Fully implicit: no explicit part, the whole right-hand side in the implicit one.
  sun.arkode = ARKStepCreate(nullptr, right_hand_side, initial.t, sun.x, sun.context);
  if (sun.arkode == nullptr) throw NumericError("integrator 'arkode': out of memory creating ARKODE");
  sun.solver = SUNLinSol_Dense(sun.x, sun.A, sun.context);

  void* mem = sun.arkode;
  check(ARKStepSetErrHandlerFn(mem, keep_message, &data), "ARKStepSetErrHandlerFn", data);
  check(ARKStepSetUserData(mem, &data), "ARKStepSetUserData", data);
  check(ARKStepSetOrder(mem, 4), "ARKStepSetOrder", data);
  check(ARKStepWFtolerances(mem, error_weights), "ARKStepWFtolerances", data);
  check(ARKStepSetLinearSolver(mem, sun.solver, sun.A), "ARKStepSetLinearSolver", data);
  check(ARKStepSetMaxNumSteps(mem, 1000000000L), "ARKStepSetMaxNumSteps", data);
  check(ARKStepSetStopTime(mem, t_end), "ARKStepSetStopTime", data);
  check(ARKStepSetMinStep(mem, options_.min_step), "ARKStepSetMinStep", data);
  if (std::isfinite(options_.max_step)) {
    check(ARKStepSetMaxStep(mem, options_.max_step), "ARKStepSetMaxStep", data);
  }
  if (options_.fixed_step) {
    check(ARKStepSetFixedStep(mem, options_.initial_step), "ARKStepSetFixedStep", data);
  } else if (options_.initial_step > 0.0) {
    check(ARKStepSetInitStep(mem, options_.initial_step), "ARKStepSetInitStep", data);
  }
}

// One output: the state at t with qdd and yd evaluated there.
void Arkode::deliver(CallbackData& data, double t, N_Vector x) {
  unpack(data, t, x);
  ++data.evaluations;
  data.qdd.resize(data.n);
  data.yd.resize(data.m);
  data.system->accelerations(data.s, data.qdd, data.yd);
  emit(*data.system, data.s, data.qdd, data.yd);
  progress(t);
}

void Arkode::collect_statistics(const Sundials& sun, const CallbackData& data) {
  long steps = 0, test_failures = 0, convergence_failures = 0, jacobians = 0, iterations = 0;
  ARKStepGetNumSteps(sun.arkode, &steps);
  ARKStepGetNumErrTestFails(sun.arkode, &test_failures);
  ARKStepGetNumNonlinSolvConvFails(sun.arkode, &convergence_failures);
  ARKStepGetNumJacEvals(sun.arkode, &jacobians);
  ARKStepGetNumNonlinSolvIters(sun.arkode, &iterations);
  stats_.steps = steps;
  stats_.rejected_steps = test_failures + convergence_failures;
  stats_.jacobian_evaluations = jacobians;
  stats_.newton_iterations = iterations;
  stats_.rhs_evaluations = data.evaluations;
}

State Arkode::run(DynamicSystem& system, const State& initial, double t_end) {
  if (options_.fixed_step && !(options_.initial_step > 0.0)) {
    throw OptionError("integrator 'arkode': a fixed-step run needs initial_step > 0 (the step)");
  }
  CallbackData data;
  data.system = &system;
  data.n = system.num_coordinates();
  data.m = system.num_extra_states();
  if (2 * data.n + data.m == 0) throw ModelError("integrator 'arkode': the system has no state");
  ErrorWeights weights(options_, name(), data.n, data.m);
  data.weights = &weights;
  Sundials sun;
  setup(sun, data, initial, t_end);

  // The initial output, through the same path as the others.
  deliver(data, initial.t, sun.x);

  // Advances by one step towards `target`, reporting failures.
  auto advance = [&](double target, int mode) {
    double reached = initial.t;
    const int flag = ARKStepEvolve(sun.arkode, target, sun.x, &reached, mode);
    collect_statistics(sun, data);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      ARKStepGetCurrentTime(sun.arkode, &reached);
      throw NumericError(detail::at_time(
          reached, fmt::format("integrator 'arkode' failed with {} ({}){}",
                               flag_name(flag), data.solver_message,
                               data.last_failure.empty() ? "" : "; last failure: " + data.last_failure)));
    }
    return reached;
  };
  // One step at a time (ARK_ONE_STEP, never past t_end), the output instants in each
  // step from ARKODE's Hermite interpolating polynomial: the outputs do not change the steps.
  N_Vector at = N_VClone(sun.x);
  const std::unique_ptr<std::remove_pointer_t<N_Vector>, void (*)(N_Vector)> owner(at, N_VDestroy);
  std::size_t next_output = 0;
  double t = initial.t;
  while (t < t_end) {
    t = advance(t_end, ARK_ONE_STEP);
    if (output_every_step()) {
      deliver(data, t, sun.x);
      continue;
    }
    for (; next_output < output_instants().size() && output_instants()[next_output] <= t; ++next_output) {
      const double ti = output_instants()[next_output];
      check(ARKStepGetDky(sun.arkode, ti, 0, at), "ARKStepGetDky", data);
      deliver(data, ti, at);
    }
  }
  collect_statistics(sun, data);
  unpack(data, t_end, sun.x);
  return data.s;
}

}  // namespace

std::unique_ptr<Integrator> make_arkode(IntegratorOptions options) {
  return std::make_unique<Arkode>(std::move(options));
}

}  // namespace symdyn::runtime
