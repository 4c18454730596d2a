#pragma once
// Private to the runtime: the first-order form x = (q, qd, y) (2n + m),
// dx/dt = (qd, qdd, yd), shared by the explicit Runge-Kutta methods (rk4, dopri5,
// dop853).

#include <algorithm>
#include <cmath>
#include <string>

#include <symdyn/runtime/detail/stepping_integrator.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime::detail {

class ExplicitIntegrator : public SteppingIntegrator {
 public:
  using SteppingIntegrator::SteppingIntegrator;

 protected:
  void start(const State& initial) override {
    n_ = system_->num_coordinates();
    m_ = system_->num_extra_states();
    current_ = initial;
    x_.resize(2 * n_ + m_);
    x_ << initial.q, initial.qd, initial.y;
    dx_.resize(x_.size());
    const std::string bad = derivative(initial.t, x_, dx_);
    if (!bad.empty()) throw NumericError(at_time(initial.t, bad));
    unpack_rates(dx_, qdd_, yd_);
  }

  // dx = (qd, qdd, yd) at (t, x). "" or what is not finite (then dx is meaningless).
  std::string derivative(double t, const Vector& x, Vector& dx) {
    scratch_.t = t;
    unpack(x, scratch_);
    qdd_scratch_.resize(n_);
    yd_scratch_.resize(m_);
    try {
      accelerations(scratch_, qdd_scratch_, yd_scratch_);
    } catch (const NumericError& e) {  // the system's own report of a bad state
      return e.what();
    }
    std::string bad = non_finite_value(*system_, scratch_, qdd_scratch_, yd_scratch_);
    if (!bad.empty()) return bad;
    dx.resize(x.size());
    dx << scratch_.qd, qdd_scratch_, yd_scratch_;
    return {};
  }

  // Hairer's starting step for a method of the given order: the step an Euler step
  // with error 0.01 would take, from |x0|, |f0| and a difference estimate of |f'|.
  // k is scratch (2n + m).
  double starting_step(double t_end, int order, Vector& k) {
    const double span = t_end - current_.t;
    const double d0 = rms_scaled(x_, x_, x_);
    const double d1 = rms_scaled(dx_, x_, x_);
    double h0 = (d0 < 1e-10 || d1 < 1e-10) ? 1e-6 * span : 0.01 * d0 / d1;
    h0 = std::min({h0, options_.max_step, span});
    Vector xs = x_ + h0 * dx_;
    if (!derivative(current_.t + h0, xs, k).empty()) return h0;
    const double d2 = rms_scaled(k - dx_, x_, x_) / h0;
    const double dmax = std::max(d1, d2);
    const double h1 =
        dmax <= 1e-15 ? std::max(1e-6 * span, h0 * 1e-3) : std::pow(0.01 / dmax, 1.0 / order);
    return std::min({100.0 * h0, h1, span});
  }

  // The RMS of v under the error weights of a step from x0 to x1.
  double rms_scaled(const Vector& v, const Vector& x0, const Vector& x1) {
    weights_->update(x0, x1);
    return weights_->rms(v);
  }

  void unpack(const Vector& x, State& s) const {
    s.q = x.head(n_);
    s.qd = x.segment(n_, n_);
    s.y = x.tail(m_);
  }
  void unpack_rates(const Vector& dx, Vector& qdd, Vector& yd) const {
    qdd = dx.segment(n_, n_);
    yd = dx.tail(m_);
  }

  // Dense output: s, qdd and yd at t from the interpolated x, its rates evaluated
  // there into the scratch dx.
  void interpolated(double t, const Vector& x, Vector& dx, State& s, Vector& qdd, Vector& yd) {
    const std::string bad = derivative(t, x, dx);
    if (!bad.empty()) throw NumericError(at_time(t, bad + " (dense output)"));
    s.t = t;
    unpack(x, s);
    unpack_rates(dx, qdd, yd);
  }

  // Commits x1 at t1 with its derivative dx1.
  void commit(double t1, const Vector& x1, const Vector& dx1) {
    x_ = x1;
    dx_ = dx1;
    current_.t = t1;
    unpack(x_, current_);
    unpack_rates(dx_, qdd_, yd_);
  }

  int n_ = 0;
  int m_ = 0;
  Vector x_;   // (2n + m) at current_
  Vector dx_;  // (2n + m) at current_

 private:
  State scratch_;
  Vector qdd_scratch_, yd_scratch_;
};

}  // namespace symdyn::runtime::detail
