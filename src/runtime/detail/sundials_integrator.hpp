#pragma once
// Private to the runtime: one integrator over any SUNDIALS solver whose calls
// are those of CVODE under its own prefix (CVODE's CVode*, ARKODE's ARKStep*).
// A solver is a table of its functions (SundialsSolver); cvode_integrator.cpp
// and arkode_integrator.cpp each fill one.
//
// The run: x = (q, qd, y) (2n + m) with dense Jacobian and linear solver, the
// error weights of ErrorWeights (the solver's WFtolerances), one step at a time
// (never past t_end), each output instant in a step from the solver's
// interpolating polynomial, so that outputs never change the steps.

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include <memory>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime::detail {

struct SundialsSolver {
  const char* name;   // make_integrator's name: "cvode"
  const char* title;  // in messages: "CVODE"
  int one_step;       // the evolve mode of one internal step (CV_ONE_STEP)
  // Creates the solver's memory at (t0, x) with the first-order right-hand
  // side; null when out of memory. Then `initialize` (named `initialize_call`
  // in messages), after the error handler is set.
  void* (*create)(SUNContext context, N_Vector x, double t0);
  int (*initialize)(void* mem, N_Vector x, double t0);
  const char* initialize_call;
  void (*free)(void** mem);
  char* (*flag_name)(long flag);  // allocated with malloc
  int (*set_error_handler)(void* mem, void (*)(int, const char*, const char*, char*, void*),
                           void* data);
  int (*set_user_data)(void* mem, void* data);
  int (*set_weights)(void* mem, int (*)(N_Vector, N_Vector, void*));
  int (*set_linear_solver)(void* mem, SUNLinearSolver solver, SUNMatrix A);
  // The Jacobian callback (CVodeSetJacFn): ours, jacobian() in sundials_support.hpp.
  int (*set_jacobian)(void* mem, int (*)(double t, N_Vector x, N_Vector fx, SUNMatrix J, void* data,
                                         N_Vector, N_Vector, N_Vector));
  int (*set_max_steps)(void* mem, long steps);
  int (*set_stop_time)(void* mem, double t);
  int (*set_min_step)(void* mem, double h);
  int (*set_max_step)(void* mem, double h);
  int (*set_initial_step)(void* mem, double h);
  int (*set_fixed_step)(void* mem, double h);  // null: the solver is adaptive only
  int (*evolve)(void* mem, double target, N_Vector x, double* reached, int mode);
  int (*current_time)(void* mem, double* t);
  int (*interpolate)(void* mem, double t, int derivative, N_Vector x);
  int (*steps)(void* mem, long* n);
  int (*error_test_failures)(void* mem, long* n);
  int (*convergence_failures)(void* mem, long* n);
  int (*jacobian_evaluations)(void* mem, long* n);
  int (*newton_iterations)(void* mem, long* n);
  const char* prefix;  // of the calls' names in messages: "CVode"
  // > 0: each step's error is held within rtol^step_power of the error weights (the
  // tolerance transformed, as newmark.hpp's), but the solver's tolerance not below
  // kTightestSolverTolerance (sundials_integrator.cpp). 0: the weights as they are.
  double step_power = 0.0;
};

std::unique_ptr<Integrator> make_sundials_integrator(IntegratorOptions options,
                                                     const SundialsSolver& solver);

}  // namespace symdyn::runtime::detail
