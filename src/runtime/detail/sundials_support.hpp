#pragma once
// Private to the runtime: what the SUNDIALS wrappers (cvode, arkode) share, the
// callbacks on the first-order form x = (q, qd, y) (2n + m) and the data they see.

#include <nvector/nvector_serial.h>
#include <sundials/sundials_matrix.h>

#include <exception>
#include <string>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime::detail {

// What the C callbacks see (user data): the system, scratch, and what went wrong.
struct CallbackData {
  DynamicSystem* system = nullptr;
  int n = 0;
  int m = 0;
  State s;
  Vector qdd, yd;
  Vector x;  // (2n + m) the solver's state for the error weights, copied: no allocation per step
  Vector scale;  // (2n + m) the size below which a difference step does not shrink: q_scale, else 1
  Vector f0;     // (n) the accelerations at the Jacobian's point
  Matrix dqdd_dq, dqdd_dqd;  // (n x n) the system's exact derivatives, where it has them
  long evaluations = 0;
  std::string last_failure;    // last non-finite value or NumericError, with its time
  std::string solver_message;  // the solver's own message of its last error
  std::exception_ptr error;    // any other exception, rethrown after the solver returns
  ErrorWeights* weights = nullptr;
};

// Unpacks x = (q, qd, y) into data.s at t.
void unpack(CallbackData& d, double t, N_Vector x);

// dx = (qd, qdd, yd). Returns 0, 1 (recoverable: the solver retries with a smaller
// step) or -1 (unrecoverable: the exception is kept and rethrown).
int right_hand_side(realtype t, N_Vector x, N_Vector dx, void* user);

// J = d(qd, qdd, yd)/d(q, qd, y) (2n + m square): the rows of qd exactly (0, I, 0),
// the others exactly where the system knows them (DynamicSystem::exact_acceleration_derivatives),
// else by forward differences of the accelerations, a step of sqrt(eps)·max(|x_j|,
// scale_j). Ours rather than the solver's difference Jacobian, which allocates at each
// call and differences the rows it could know. Returns as right_hand_side.
int jacobian(realtype t, N_Vector x, N_Vector fx, SUNMatrix J, void* user, N_Vector, N_Vector,
             N_Vector);

// The solver's error weights are the inverses of ours (ErrorWeights), at the current x.
int error_weights(N_Vector x, N_Vector ewt, void* user);

// Keeps the solver's message of its last error in the CallbackData.
void keep_message(int, const char*, const char* function, char* message, void* user);

}  // namespace symdyn::runtime::detail
