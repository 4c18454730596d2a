#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include <symdyn/runtime/detail/explicit_integrator.hpp>
#include <symdyn/runtime/detail/runge_kutta.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

namespace {

class Rk4 final : public detail::ExplicitIntegrator {
 public:
  using ExplicitIntegrator::ExplicitIntegrator;
  std::string_view name() const override { return "rk4"; }

 private:
  double first_step(double) override { return options_.initial_step; }
  bool fixed_step_only() const override { return true; }

  // x1 = x0 + h/6·(k1 + 2·k2 + 2·k3 + k4)
  int order() const override { return 4; }
  detail::StepOutcome attempt(double h, bool) override {
    const double t = current_.t;
    const std::array<std::pair<double, const Vector*>, 3> stages = {
        {{0.5 * h, &dx_}, {0.5 * h, &k2_}, {h, &k3_}}};
    Vector* results[3] = {&k2_, &k3_, &k4_};
    for (int s = 0; s < 3; ++s) {
      const double c = stages[s].first;
      xs_ = x_ + c * *stages[s].second;
      const std::string bad = derivative(t + c, xs_, *results[s]);
      if (!bad.empty()) return {false, h / 4.0, detail::at_time(t + c, bad)};
    }
    xs_ = x_ + (h / 6.0) * (dx_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
    const std::string bad = derivative(t + h, xs_, k1_next_);
    if (!bad.empty()) return {false, h / 4.0, detail::at_time(t + h, bad)};
    commit(t + h, xs_, k1_next_);
    return {true, h, {}};
  }

  Vector k2_, k3_, k4_, k1_next_, xs_;
};

// Dormand-Prince 5(4) tableau (c, a), fifth-order weights (= a7), error weights e
// (fifth minus fourth order) and the continuous extension's d.
constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                 a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                 a65 = -5103.0 / 18656;
constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192, a75 = -2187.0 / 6784,
                 a76 = 11.0 / 84;
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200,
                 e6 = 22.0 / 525, e7 = -1.0 / 40;
constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                 d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                 d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;

class Dopri5 final : public detail::ExplicitIntegrator {
 public:
  using ExplicitIntegrator::ExplicitIntegrator;
  std::string_view name() const override { return "dopri5"; }

 private:
  void start(const State& initial) override {
    ExplicitIntegrator::start(initial);
    error_old_ = 1e-4;
    rejected_ = false;
  }
  double first_step(double t_end) override;
  int order() const override { return 5; }
  detail::StepOutcome attempt(double h, bool fixed) override;
  void interpolate(double t, State& s, Vector& qdd, Vector& yd) override;

  Vector k2_, k3_, k4_, k5_, k6_, k7_, xs_, x1_;
  // Continuous extension of the last accepted step [t_old, t_old + h_old].
  Vector r1_, r2_, r3_, r4_, r5_;
  double t_old_ = 0.0;
  double h_old_ = 0.0;
  double error_old_ = 1e-4;
  bool rejected_ = false;
};

double Dopri5::first_step(double t_end) {
  return starting_step(t_end, 5, k2_);
}

detail::StepOutcome Dopri5::attempt(double h, bool fixed) {
  const double t = current_.t;
  const Vector& k1 = dx_;
  // Each stage: xs = x + h·sum(a_sj·k_j), k_s = f(t + c_s·h, xs).
  auto stage = [&](double c, Vector& k) -> std::string {
    const std::string bad = derivative(t + c * h, xs_, k);
    return bad.empty() ? bad : detail::at_time(t + c * h, bad);
  };
  std::string bad;
  xs_ = x_ + h * (a21 * k1);
  if (bad = stage(c2, k2_); bad.empty()) {
    xs_ = x_ + h * (a31 * k1 + a32 * k2_);
    bad = stage(c3, k3_);
  }
  if (bad.empty()) {
    xs_ = x_ + h * (a41 * k1 + a42 * k2_ + a43 * k3_);
    bad = stage(c4, k4_);
  }
  if (bad.empty()) {
    xs_ = x_ + h * (a51 * k1 + a52 * k2_ + a53 * k3_ + a54 * k4_);
    bad = stage(c5, k5_);
  }
  if (bad.empty()) {
    xs_ = x_ + h * (a61 * k1 + a62 * k2_ + a63 * k3_ + a64 * k4_ + a65 * k5_);
    bad = stage(1.0, k6_);
  }
  if (bad.empty()) {
    x1_ = x_ + h * (a71 * k1 + a73 * k3_ + a74 * k4_ + a75 * k5_ + a76 * k6_);
    xs_ = x1_;
    bad = stage(1.0, k7_);
  }
  if (!bad.empty()) {
    rejected_ = true;
    return {false, h / 4.0, bad};
  }

  double next = h;
  if (!fixed) {
    xs_ = h * (e1 * k1 + e3 * k3_ + e4 * k4_ + e5 * k5_ + e6 * k6_ + e7 * k7_);
    const double error = rms_scaled(xs_, x_, x1_);
    // PI controller: h_new = h·safe·err^-0.17·err_old^0.04, change within [1/5, 10].
    const double fac11 = std::pow(error, 0.17);
    if (error > 1.0) {
      rejected_ = true;
      return {false, h / std::min(5.0, fac11 / 0.9), {}};
    }
    const double fac = std::clamp(fac11 / std::pow(error_old_, 0.04) / 0.9, 0.1, 5.0);
    next = h / fac;
    if (rejected_) next = std::min(next, h);  // no growth right after a rejection
    error_old_ = std::max(error, 1e-4);
    rejected_ = false;
  }

  // Continuous extension: x(t_old + th·h) = r1 + th·(r2 + (1-th)·(r3 + th·(r4 + (1-th)·r5))).
  r1_ = x_;
  r2_ = x1_ - x_;
  r3_ = h * k1 - r2_;
  r4_ = r2_ - h * k7_ - r3_;
  r5_ = h * (d1 * k1 + d3 * k3_ + d4 * k4_ + d5 * k5_ + d6 * k6_ + d7 * k7_);
  t_old_ = t;
  h_old_ = h;
  commit(t + h, x1_, k7_);
  return {true, next, {}};
}

// The state from the continuous extension; qdd and yd evaluated there.
void Dopri5::interpolate(double t, State& s, Vector& qdd, Vector& yd) {
  const double th = (t - t_old_) / h_old_;
  const double th1 = 1.0 - th;
  xs_ = r1_ + th * (r2_ + th1 * (r3_ + th * (r4_ + th1 * r5_)));
  interpolated(t, xs_, k2_, s, qdd, yd);
}

}  // namespace

std::unique_ptr<Integrator> make_rk4(IntegratorOptions options) {
  return std::make_unique<Rk4>(std::move(options));
}

std::unique_ptr<Integrator> make_dopri5(IntegratorOptions options) {
  return std::make_unique<Dopri5>(std::move(options));
}

}  // namespace symdyn::runtime
