#pragma once
// Private to the runtime: the step loop shared by the one-step integrators
// (newmark, generalized-alpha, rk4, dopri5, dop853, midpoint).
//
// Why a shared loop: dense output at the output instants, step-size bounds, the
// underflow test, rejected-step bookkeeping and progress are the same for every
// one-step method; a method only says how to attempt one step and what step to try
// next, and may replace the Hermite interpolant by its own continuous extension.

#include <optional>
#include <string>

#include <symdyn/runtime/detail/non_finite.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime::detail {

// The outcome of one step attempt.
struct StepOutcome {
  bool accepted = false;
  double next_step = 0.0;  // the step to try next (before the min/max bounds)
  std::string failure;     // why a step failed (Newton, non-finite), with its time; "" otherwise
};

// Step failures (a non-finite value, a Newton iteration that diverged) that
// follow one another without the integrator getting back to the step that
// first failed: the solution creeps towards a place it cannot pass (asin's
// argument at 1), which smaller steps only approach. Recovery is an accepted
// step as long as the first failed one, or kRecoverySteps accepted steps in a row.
class FailureStreak {
 public:
  static constexpr int kLimit = 12;  // 4^12: steps divided by 1.7e7
  static constexpr int kRecoverySteps = 50;
  // Records a failed step of size h; true when the streak reaches kLimit.
  bool failed(double h) {
    if (count_ == 0) first_ = h;
    accepted_ = 0;
    return ++count_ >= kLimit;
  }
  void accepted(double h) {
    if (count_ > 0 && (h >= first_ || ++accepted_ >= kRecoverySteps)) count_ = 0;
  }
  int count() const { return count_; }
  double first_step() const { return first_; }

 private:
  int count_ = 0;
  int accepted_ = 0;
  double first_ = 0.0;
};

class SteppingIntegrator : public Integrator {
 public:
  using Integrator::Integrator;

 protected:
  // Sets current_, qdd_ (n), yd_ (m) at the initial state, consistent with the equations.
  virtual void start(const State& initial) = 0;

  // Tries a step of h from current_. If accepted, current_, qdd_ and yd_ are at
  // current_.t + h; otherwise they are unchanged. With fixed = true there is no
  // error test: the step is accepted unless it failed.
  virtual StepOutcome attempt(double h, bool fixed) = 0;

  // The first step when options_.initial_step is 0.
  virtual double first_step(double t_end) = 0;

  // Whether the method only has fixed steps (rk4), whatever options_.fixed_step says.
  virtual bool fixed_step_only() const { return false; }

  // The order p of the method at a fixed step (global error ~ h^p).
  virtual int order() const = 0;
  int fixed_step_order() const final {
    return options_.fixed_step || fixed_step_only() ? order() : 0;
  }
  // Whether the method is its own adjoint (a step of -h undoes a step of h).
  virtual bool symmetric() const { return false; }
  bool fixed_step_symmetric() const final { return fixed_step_order() > 0 && symmetric(); }

  // What set the last step size, for the message of a step below min_step: "" or,
  // say, "the local error of qd of coordinate 'crank'".
  virtual std::string step_limit() const { return {}; }

  // Dense output: the state, qdd and yd at t in the last accepted step, from
  // previous_ to current_. By default the quintic Hermite interpolant of q from
  // (q, qd, qdd) at both ends (its derivative gives qd), the cubic ones of qd from
  // (qd, qdd) (its derivative gives qdd) and of y from (y, yd) (its derivative gives
  // yd): no evaluation of the system.
  virtual void interpolate(double t, State& s, Vector& qdd, Vector& yd);

  // Evaluations through the system, counted.
  void accelerations(const State& s, Vector& qdd, Vector& yd);
  void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f, Vector& g);

  DynamicSystem* system_ = nullptr;
  std::optional<ErrorWeights> weights_;  // set before start()
  State current_;
  Vector qdd_;      // (n) at current_
  Vector yd_;       // (m) at current_
  State previous_;  // the start of the last accepted step
  Vector previous_qdd_, previous_yd_;

 private:
  State run(DynamicSystem& system, const State& initial, double t_end) final;
  void deliver(double t_previous, std::size_t& next_output);
  double initial_step(double t_end);
  // Throws the NumericError of a failed fixed step from previous_ (see the .cpp).
  [[noreturn]] void fixed_step_failed(const std::string& failure, double step,
                                      const State& initial) const;

  State dense_;  // an interpolated output instant, kept: outputs allocate nothing
  Vector dense_qdd_, dense_yd_;
};

}  // namespace symdyn::runtime::detail
