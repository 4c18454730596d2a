#include <arkode/arkode_arkstep.h>

#include <symdyn/runtime/detail/arkode_integrator.hpp>
#include <symdyn/runtime/detail/sundials_integrator.hpp>
#include <symdyn/runtime/detail/sundials_support.hpp>

namespace symdyn::runtime {

namespace {

// ARKODE's ARKStep, fully implicit (no explicit part: the whole right-hand side
// in the implicit one), order 4 (SDIRK 5-3-4), Newton on a dense linear system.
const detail::SundialsSolver arkode{
    .name = "arkode",
    .title = "ARKODE",
    .one_step = ARK_ONE_STEP,
    .create =
        [](SUNContext context, N_Vector x, double t0) {
          return ARKStepCreate(nullptr, detail::right_hand_side, t0, x, context);
        },
    .initialize = [](void* mem, N_Vector, double) { return ARKStepSetOrder(mem, 4); },
    .initialize_call = "SetOrder",
    .free = ARKStepFree,
    .flag_name = ARKStepGetReturnFlagName,
    .set_error_handler = ARKStepSetErrHandlerFn,
    .set_user_data = ARKStepSetUserData,
    .set_weights = ARKStepWFtolerances,
    .set_linear_solver = ARKStepSetLinearSolver,
    .set_jacobian = ARKStepSetJacFn,
    .set_max_steps = ARKStepSetMaxNumSteps,
    .set_stop_time = ARKStepSetStopTime,
    .set_min_step = ARKStepSetMinStep,
    .set_max_step = ARKStepSetMaxStep,
    .set_initial_step = ARKStepSetInitStep,
    .set_fixed_step = ARKStepSetFixedStep,
    .evolve = ARKStepEvolve,
    .current_time = ARKStepGetCurrentTime,
    .interpolate = ARKStepGetDky,
    .steps = ARKStepGetNumSteps,
    .error_test_failures = ARKStepGetNumErrTestFails,
    .convergence_failures = ARKStepGetNumNonlinSolvConvFails,
    .jacobian_evaluations = ARKStepGetNumJacEvals,
    .newton_iterations = ARKStepGetNumNonlinSolvIters,
    .prefix = "ARKStep",
};

}  // namespace

std::unique_ptr<Integrator> make_arkode(IntegratorOptions options) {
  return detail::make_sundials_integrator(std::move(options), arkode);
}

}  // namespace symdyn::runtime
