#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <string>
#include <type_traits>
#include <utility>

#include <symdyn/runtime/detail/non_finite.hpp>
#include <symdyn/runtime/detail/sundials_integrator.hpp>
#include <symdyn/runtime/detail/sundials_support.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime::detail {

namespace {

// Owns the SUNDIALS objects of one run.
struct Sundials {
  explicit Sundials(const SundialsSolver& s) : solver(s) {}
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  ~Sundials() {
    if (mem != nullptr) solver.free(&mem);
    if (linear_solver != nullptr) SUNLinSolFree(linear_solver);
    if (A != nullptr) SUNMatDestroy(A);
    if (x != nullptr) N_VDestroy(x);
    if (context != nullptr) SUNContext_Free(&context);
  }

  const SundialsSolver& solver;
  SUNContext context = nullptr;
  N_Vector x = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver linear_solver = nullptr;
  void* mem = nullptr;
};

// The tightest tolerance the solver is given, where rounding takes over (CVODE may refuse
// a long run before: "too much accuracy requested", a failed run for global_tolerance).
constexpr double kTightestSolverTolerance = 1e-14;

class SundialsIntegrator final : public Integrator {
 public:
  SundialsIntegrator(IntegratorOptions options, const SundialsSolver& solver)
      : Integrator(std::move(options)), solver_(solver) {}
  std::string_view name() const override { return solver_.name; }

 private:
  // The factor of both tolerances the solver is given: rtol^step_power, at most 1, the
  // solver's relative tolerance not below kTightestSolverTolerance.
  double tolerance_factor() const {
    const double rtol = options_.relative_tolerance;
    if (!(solver_.step_power > 0.0)) return 1.0;
    return std::min(1.0,
                    std::max(std::pow(rtol, solver_.step_power), kTightestSolverTolerance / rtol));
  }
  // Below it the factor stops at kTightestSolverTolerance: nothing changes.
  double tightest_tolerance() const override {
    return solver_.step_power > 0.0
               ? std::pow(kTightestSolverTolerance, 1.0 / (1.0 + solver_.step_power))
               : Integrator::tightest_tolerance();
  }
  State run(DynamicSystem& system, const State& initial, double t_end) override;
  void setup(Sundials& sun, CallbackData& data, const State& initial, double t_end);
  void deliver(CallbackData& data, double t, N_Vector x);
  void collect_statistics(const Sundials& sun, const CallbackData& data);
  std::string flag_name(int flag) const;
  // Throws NumericError for a negative flag of the call <prefix><call>.
  void check(int flag, const char* call, const CallbackData& data) const;

  const SundialsSolver& solver_;
};

std::string SundialsIntegrator::flag_name(int flag) const {
  char* name = solver_.flag_name(flag);
  std::string copy = name != nullptr ? name : fmt::format("flag {}", flag);
  std::free(name);
  return copy;
}

void SundialsIntegrator::check(int flag, const char* call, const CallbackData& data) const {
  if (flag >= 0) return;
  throw NumericError(fmt::format("integrator '{}': {}{} failed with {} ({})", name(),
                                 solver_.prefix, call, flag_name(flag), data.solver_message));
}

void SundialsIntegrator::setup(Sundials& sun, CallbackData& data, const State& initial,
                               double t_end) {
  const int size = 2 * data.n + data.m;
  if (SUNContext_Create(nullptr, &sun.context) != 0) {
    throw NumericError(fmt::format("integrator '{}': SUNContext_Create failed", name()));
  }
  sun.x = N_VNew_Serial(size, sun.context);
  sun.A = SUNDenseMatrix(size, size, sun.context);
  if (sun.x != nullptr)
    Eigen::Map<Vector>(N_VGetArrayPointer(sun.x), size) << initial.q, initial.qd, initial.y;
  if (sun.x != nullptr) sun.mem = solver_.create(sun.context, sun.x, initial.t);
  if (sun.x == nullptr || sun.A == nullptr || sun.mem == nullptr) {
    throw NumericError(
        fmt::format("integrator '{}': out of memory creating {}", name(), solver_.title));
  }
  sun.linear_solver = SUNLinSol_Dense(sun.x, sun.A, sun.context);

  void* mem = sun.mem;
  check(solver_.set_error_handler(mem, keep_message, &data), "SetErrHandlerFn", data);
  check(solver_.initialize(mem, sun.x, initial.t), solver_.initialize_call, data);
  check(solver_.set_user_data(mem, &data), "SetUserData", data);
  check(solver_.set_weights(mem, error_weights), "WFtolerances", data);
  check(solver_.set_linear_solver(mem, sun.linear_solver, sun.A), "SetLinearSolver", data);
  check(solver_.set_jacobian(mem, jacobian), "SetJacFn", data);
  check(solver_.set_max_steps(mem, 1000000000L), "SetMaxNumSteps", data);
  check(solver_.set_stop_time(mem, t_end), "SetStopTime", data);
  check(solver_.set_min_step(mem, options_.min_step), "SetMinStep", data);
  if (std::isfinite(options_.max_step))
    check(solver_.set_max_step(mem, options_.max_step), "SetMaxStep", data);
  if (options_.fixed_step) {
    check(solver_.set_fixed_step(mem, options_.initial_step), "SetFixedStep", data);
  } else if (options_.initial_step > 0.0) {
    check(solver_.set_initial_step(mem, options_.initial_step), "SetInitStep", data);
  }
}

// One output: the state at t with qdd and yd evaluated there.
void SundialsIntegrator::deliver(CallbackData& data, double t, N_Vector x) {
  unpack(data, t, x);
  ++data.evaluations;
  data.qdd.resize(data.n);
  data.yd.resize(data.m);
  data.system->accelerations(data.s, data.qdd, data.yd);
  emit(*data.system, data.s, data.qdd, data.yd);
  progress(t);
}

void SundialsIntegrator::collect_statistics(const Sundials& sun, const CallbackData& data) {
  long steps = 0, test_failures = 0, convergence_failures = 0, jacobians = 0, iterations = 0;
  solver_.steps(sun.mem, &steps);
  solver_.error_test_failures(sun.mem, &test_failures);
  solver_.convergence_failures(sun.mem, &convergence_failures);
  solver_.jacobian_evaluations(sun.mem, &jacobians);
  solver_.newton_iterations(sun.mem, &iterations);
  stats_.steps = steps;
  stats_.rejected_steps = test_failures + convergence_failures;
  stats_.jacobian_evaluations = jacobians;
  stats_.newton_iterations = iterations;
  stats_.rhs_evaluations = data.evaluations;
}

State SundialsIntegrator::run(DynamicSystem& system, const State& initial, double t_end) {
  if (options_.fixed_step && solver_.set_fixed_step == nullptr) {
    throw OptionError(fmt::format("integrator '{}': fixed_step is not available ({} is adaptive)",
                                  name(), solver_.title));
  }
  if (options_.fixed_step && !(options_.initial_step > 0.0)) {
    throw OptionError(
        fmt::format("integrator '{}': a fixed-step run needs initial_step > 0 (the step)", name()));
  }
  CallbackData data;
  data.system = &system;
  data.n = system.num_coordinates();
  data.m = system.num_extra_states();
  if (2 * data.n + data.m == 0)
    throw ModelError(fmt::format("integrator '{}': the system has no state", name()));
  IntegratorOptions transformed = options_;
  transformed.relative_tolerance *= tolerance_factor();
  transformed.absolute_tolerance *= tolerance_factor();
  ErrorWeights weights(transformed, name(), data.n, data.m);
  data.weights = &weights;
  data.scale = Vector::Ones(2 * data.n + data.m);
  for (std::size_t i = 0; i < options_.q_scale.size(); ++i)
    data.scale[static_cast<Eigen::Index>(i)] = options_.q_scale[i];
  data.x.resize(2 * data.n + data.m);
  data.qdd.resize(data.n);
  data.yd.resize(data.m);
  Sundials sun(solver_);
  setup(sun, data, initial, t_end);

  // The initial output, through the same path as the others.
  deliver(data, initial.t, sun.x);

  // Advances by one step towards `target`, reporting failures.
  auto advance = [&](double target, int mode) {
    double reached = initial.t;
    const int flag = solver_.evolve(sun.mem, target, sun.x, &reached, mode);
    collect_statistics(sun, data);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      solver_.current_time(sun.mem, &reached);
      throw NumericError(at_time(
          reached,
          fmt::format("integrator '{}' failed with {} ({}){}", name(), flag_name(flag),
                      data.solver_message,
                      data.last_failure.empty() ? "" : "; last failure: " + data.last_failure)));
    }
    return reached;
  };
  // One step at a time (never past t_end), the output instants in each step
  // from the solver's interpolating polynomial: the outputs do not change the steps.
  N_Vector at = N_VClone(sun.x);
  const std::unique_ptr<std::remove_pointer_t<N_Vector>, void (*)(N_Vector)> owner(at, N_VDestroy);
  std::size_t next_output = 0;
  double t = initial.t;
  // Each step's ends, for DynamicSystem::check_step.
  State from = initial, to = initial;
  const auto state_at = [&](double ts, State& s) {
    unpack(data, ts, sun.x);
    s = data.s;
  };
  while (t < t_end) {
    t = advance(t_end, solver_.one_step);
    std::swap(from, to);
    state_at(t, to);
    system.check_step(from, to);
    if (output_every_step()) {
      deliver(data, t, sun.x);
      continue;
    }
    for (; next_output < output_instants().size() && output_instants()[next_output] <= t;
         ++next_output) {
      const double ti = output_instants()[next_output];
      check(solver_.interpolate(sun.mem, ti, 0, at), "GetDky", data);
      deliver(data, ti, at);
    }
  }
  collect_statistics(sun, data);
  unpack(data, t_end, sun.x);
  return data.s;
}

}  // namespace

std::unique_ptr<Integrator> make_sundials_integrator(IntegratorOptions options,
                                                     const SundialsSolver& solver) {
  return std::make_unique<SundialsIntegrator>(std::move(options), solver);
}

}  // namespace symdyn::runtime::detail
