#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>

#include <symdyn/runtime/detail/cvode_integrator.hpp>
#include <symdyn/runtime/detail/sundials_integrator.hpp>
#include <symdyn/runtime/detail/sundials_support.hpp>

namespace symdyn::runtime {

namespace {

// CVODE: BDF orders 1-5 with Newton on a dense linear system.
const detail::SundialsSolver cvode{
    .name = "cvode",
    .title = "CVODE",
    .one_step = CV_ONE_STEP,
    .create = [](SUNContext context, N_Vector, double) { return CVodeCreate(CV_BDF, context); },
    .initialize = [](void* mem, N_Vector x,
                     double t0) { return CVodeInit(mem, detail::right_hand_side, t0, x); },
    .initialize_call = "Init",
    .free = CVodeFree,
    .flag_name = CVodeGetReturnFlagName,
    .set_error_handler = CVodeSetErrHandlerFn,
    .set_user_data = CVodeSetUserData,
    .set_weights = CVodeWFtolerances,
    .set_linear_solver = CVodeSetLinearSolver,
    .set_jacobian = CVodeSetJacFn,
    .set_max_steps = CVodeSetMaxNumSteps,
    .set_stop_time = CVodeSetStopTime,
    .set_min_step = CVodeSetMinStep,
    .set_max_step = CVodeSetMaxStep,
    .set_initial_step = CVodeSetInitStep,
    .set_fixed_step = nullptr,
    .evolve = CVode,
    .current_time = CVodeGetCurrentTime,
    .interpolate = CVodeGetDky,
    .steps = CVodeGetNumSteps,
    .error_test_failures = CVodeGetNumErrTestFails,
    .convergence_failures = CVodeGetNumNonlinSolvConvFails,
    .jacobian_evaluations = CVodeGetNumJacEvals,
    .newton_iterations = CVodeGetNumNonlinSolvIters,
    .prefix = "CVode",
    .step_power = 1.0 / 3.0,
};

}  // namespace

std::unique_ptr<Integrator> make_cvode(IntegratorOptions options) {
  return detail::make_sundials_integrator(std::move(options), cvode);
}

}  // namespace symdyn::runtime
