#include <fmt/format.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <symdyn/runtime/detail/non_finite.hpp>
#include <symdyn/runtime/detail/sundials_support.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime::detail {

void unpack(CallbackData& d, double t, N_Vector x) {
  const Eigen::Map<const Vector> xv(N_VGetArrayPointer(x), 2 * d.n + d.m);
  d.s.t = t;
  d.s.q = xv.head(d.n);
  d.s.qd = xv.segment(d.n, d.n);
  d.s.y = xv.tail(d.m);
}

// A callback's body run for SUNDIALS: a NumericError is a failure it may recover
// from by a shorter step (1, its message kept in d); anything else stops it (-1)
// and is rethrown once SUNDIALS has returned.
template <class Body>
int guarded(CallbackData& d, realtype t, Body body) {
  try {
    return body();
  } catch (const NumericError& e) {
    d.last_failure = at_time(t, e.what());
    return 1;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

// dx = (qd, qdd, yd); a failure is kept in d for the message.
int right_hand_side(realtype t, N_Vector x, N_Vector dx, void* user) {
  auto& d = *static_cast<CallbackData*>(user);
  return guarded(d, t, [&] {
    unpack(d, t, x);
    ++d.evaluations;
    d.qdd.resize(d.n);
    d.yd.resize(d.m);
    d.system->accelerations(d.s, d.qdd, d.yd);
    const std::string bad = non_finite_value(*d.system, d.s, d.qdd, d.yd);
    if (!bad.empty()) {
      d.last_failure = at_time(t, bad);
      return 1;
    }
    Eigen::Map<Vector> out(N_VGetArrayPointer(dx), 2 * d.n + d.m);
    out << d.s.qd, d.qdd, d.yd;
    return 0;
  });
}

int jacobian(realtype t, N_Vector x, N_Vector fx, SUNMatrix J, void* user, N_Vector, N_Vector,
             N_Vector) {
  auto& d = *static_cast<CallbackData*>(user);
  const int n = d.n, m = d.m, size = 2 * n + m;
  Eigen::Map<Matrix> jac(SUNDenseMatrix_Data(J), size,
                         size);  // column-major, as SUNDIALS' dense matrices
  const Eigen::Map<const Vector> f0(N_VGetArrayPointer(fx), size);
  return guarded(d, t, [&] {
    unpack(d, t, x);
    jac.setZero();
    jac.block(0, n, n, n).setIdentity();
    d.f0 = f0.segment(n, n);
    if (d.system->exact_acceleration_derivatives(d.s, d.f0, d.dqdd_dq, d.dqdd_dqd)) {
      jac.block(n, 0, n, n) = d.dqdd_dq;
      jac.block(n, n, n, n) = d.dqdd_dqd;
      return 0;
    }
    for (int j = 0; j < size; ++j) {
      double& xj = j < n ? d.s.q[j] : j < 2 * n ? d.s.qd[j - n] : d.s.y[j - 2 * n];
      const double saved = xj;
      xj = saved + std::sqrt(std::numeric_limits<double>::epsilon()) *
                       std::max(std::abs(saved), d.scale[j]);
      const double step = xj - saved;  // the step as represented
      ++d.evaluations;
      d.system->accelerations(d.s, d.qdd, d.yd);
      const std::string bad = non_finite_value(*d.system, d.s, d.qdd, d.yd);
      xj = saved;
      if (!bad.empty()) {
        d.last_failure = at_time(t, bad);
        return 1;
      }
      jac.col(j).segment(n, n) = (d.qdd - f0.segment(n, n)) / step;
      jac.col(j).tail(m) = (d.yd - f0.tail(m)) / step;
    }
    return 0;
  });
}

// ewt = 1/w (SUNDIALS multiplies by its weights).
int error_weights(N_Vector x, N_Vector ewt, void* user) {
  auto& d = *static_cast<CallbackData*>(user);
  const Eigen::Map<const Vector> xv(N_VGetArrayPointer(x), 2 * d.n + d.m);
  d.x = xv;
  const Vector& w = d.weights->update(d.x, d.x);
  Eigen::Map<Vector>(N_VGetArrayPointer(ewt), w.size()) = w.cwiseInverse();
  return 0;
}

void keep_message(int, const char*, const char* function, char* message, void* user) {
  static_cast<CallbackData*>(user)->solver_message = fmt::format("{}: {}", function, message);
}

}  // namespace symdyn::runtime::detail
