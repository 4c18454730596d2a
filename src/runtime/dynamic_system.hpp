#pragma once
// The equations an integrator, the static solver and the linearizer work on.
//
// A system has n mechanical coordinates q (second order) and m extra
// first-order states y (a motor current, a controller integral, a pressure).
// Its equations, in residual form as in EasyDyn:
//
//   f(t, q, qd, qdd, y)  = M(q, t)·qdd + h(q, qd, t) - Q(t, q, qd, y)  = 0   (n)
//   g(t, q, qd, y, yd)   = yd - e(t, q, qd, y)                         = 0   (m)
//
// The mechanics are linear in qdd and the extra equations linear in yd, so
// the explicit form (qdd, yd) = solve(...) exists whenever M is regular.

#include <Eigen/Core>
#include <optional>
#include <string>

namespace symdyn::runtime {

using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
// Row by row, as the emitted code writes its matrices.
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The state carried by integrators: time, coordinates, rates and extra states.
struct State {
  double t = 0.0;
  Vector q;   // (n)
  Vector qd;  // (n)
  Vector y;   // (m)
};

class DynamicSystem {
 public:
  virtual ~DynamicSystem() = default;

  virtual int num_coordinates() const = 0;            // n
  virtual int num_extra_states() const { return 0; }  // m
  virtual std::string coordinate_name(int i) const;   // "q<i>" unless overridden
  virtual std::string extra_state_name(int i) const;  // "y<i>" unless overridden

  // Explicit form: qdd (n) and yd (m) at the state. Throws NumericError (naming the
  // state) when M is singular or a value is not finite.
  virtual void accelerations(const State& s, Vector& qdd, Vector& yd) = 0;

  // Residual form: f (n) and g (m) at the state with the given qdd and yd.
  virtual void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                        Vector& g) = 0;

  // Iteration matrices of the mechanical residual: M = df/dqdd, C = df/dqd,
  // K = df/dq (n x n each). The default differentiates the residual by central
  // differences; systems that know them exactly override it.
  virtual void jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K);

  // dqdd/dq and dqdd/dqd (n x n) of the explicit form at s, whose accelerations
  // are qdd, where the system knows them exactly (-M⁻¹·K and -M⁻¹·C); false
  // (the default) where it does not: the caller differentiates.
  virtual bool exact_acceleration_derivatives(const State& /*s*/, const Vector& /*qdd*/,
                                              Matrix& /*dqdd_dq*/, Matrix& /*dqdd_dqd*/) {
    return false;
  }

  // Cold: why M (n x n, or an iteration matrix built on it) is singular at s,
  // where the system knows a reason (a multibody model: an angle sequence at its
  // singular configuration); nullopt (the default) where it does not, and statics
  // and linearization name M's null direction instead.
  virtual std::optional<std::string> explain_singular(const State& /*s*/,
                                                      const Matrix& /*M*/) const {
    return std::nullopt;
  }

  // Called by the one-step integrators, cvode and arkode after each accepted step,
  // from `from` to `to` (t, q, qd, y at both ends), before its outputs: throws
  // NumericError (naming the time and the state) where the motion within the step
  // reaches a place the system cannot pass, which no evaluation of the step may
  // have met (a dependent parameter touching the edge of its domain between two
  // evaluations). The default does nothing.
  virtual void check_step(const State& /*from*/, const State& /*to*/) {}

  // Cold: why the equations are nearly singular at s, where the system knows a
  // reason (a multibody model: an angle sequence near its singular
  // configuration), for the message of an iteration that failed there; nullopt
  // (the default) where it does not.
  virtual std::optional<std::string> explain_near_singular(const State& /*s*/) const {
    return std::nullopt;
  }
};

}  // namespace symdyn::runtime
