// The implicit midpoint rule in (q, p) keeps the double pendulum's energy error
// bounded: over 1 000 s of the chaotic swing from the horizontal release, the
// largest energy error in the last 100 s is about that of the first 100 s, while
// rk4 at the same step (not symplectic) drifts in proportion to time. Its Newton
// iteration, with the exact Jacobians of a model that has them, converges as fast as
// with its differenced map and to the same steps.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "double_pendulum_absolute.hpp"
#include "robot3d_absolute.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace {

using namespace symdyn::runtime;

struct EnergyErrors {
  double first = 0.0;  // max |E - E0| over t <= 100 s
  double last = 0.0;   // over t >= t_end - 100 s
  double scale = 0.0;  // largest kinetic energy
};

EnergyErrors energy_errors(const char* name, double h, double t_end) {
  MultibodySystem dp(Model::from<symdyn_generated::double_pendulum_absolute>(),
                     EquationsSource::emitted);
  IntegratorOptions o;
  o.fixed_step = true;
  o.initial_step = h;
  o.output_interval = 0.1;
  const State s0 = dp.initial_state();
  const double e0 = dp.energies(s0).total();
  EnergyErrors e;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const Energies en = dp.energies(s);
    const double error = std::abs(en.total() - e0);
    if (s.t <= 100.0) e.first = std::max(e.first, error);
    if (s.t >= t_end - 100.0) e.last = std::max(e.last, error);
    e.scale = std::max(e.scale, en.kinetic);
  };
  make_integrator(name, o)->integrate(dp, s0, t_end);
  return e;
}

}  // namespace

TEST_CASE("midpoint: the double pendulum's energy error stays bounded over 1 000 s",
          "[models][midpoint]") {
  const EnergyErrors mid = energy_errors("midpoint", 0.01, 1000.0);
  const EnergyErrors rk4 = energy_errors("rk4", 0.01, 1000.0);
  INFO(
      fmt::format("midpoint: first 100 s {:.3e} J, last 100 s {:.3e} J; rk4: {:.3e} J, "
                  "{:.3e} J; energy scale {:.3g} J",
                  mid.first, mid.last, rk4.first, rk4.last, mid.scale));
  CHECK(mid.scale > 10.0);              // it swung
  CHECK(mid.first < 1e-2 * mid.scale);  // O(h²)
  CHECK(mid.last < 1.5 * mid.first);    // no drift
  CHECK(rk4.last > 5.0 * rk4.first);    // the test can tell a drift
}

TEST_CASE("midpoint: Newton with the exact Jacobians converges as fast as with differences",
          "[models][midpoint][derivatives]") {
  // robot3d flung between two stiff springs: at h = 0.01 the fixed-point iteration
  // contracts slowly and Newton takes over at every step.
  MultibodySystem system(Model::from<symdyn_generated::robot3d_absolute>());
  system.add<PointSpringDamper>("arm", BodyPoint{1, Vec3(0.1, 0.0, 0.0)},
                                BodyPoint{ground, Vec3(0.0, 0.5, 1.0)}, 500.0, 0.3);
  system.add<PointSpringDamper>("gripper", BodyPoint{2, Vec3(0.05, 0.0, 0.0)},
                                BodyPoint{ground, Vec3(0.5, 0.2, 0.6)}, 1000.0, 0.2);
  State s0 = system.initial_state();
  s0.qd.setConstant(1.0);
  IntegratorOptions o;
  o.initial_step = 0.01;
  const auto run = [&](bool exact, const State& from, double t_end) {
    system.set_exact_jacobians(exact);
    auto midpoint = make_integrator("midpoint", o);
    const State end = midpoint->integrate(system, from, t_end);
    return std::pair(end, midpoint->statistics());
  };
  // The whole run: as many Newton matrices (one a step), fewer iterations.
  const auto [exact, exact_stats] = run(true, s0, 1.0);
  const auto [differenced, differenced_stats] = run(false, s0, 1.0);
  INFO("Newton iterations: exact " << exact_stats.newton_iterations << ", differences "
                                   << differenced_stats.newton_iterations);
  CHECK(exact_stats.jacobian_evaluations == exact_stats.steps);
  CHECK(differenced_stats.jacobian_evaluations == differenced_stats.steps);
  CHECK(exact_stats.newton_iterations <= differenced_stats.newton_iterations);
  // The same steps: one from each of the states along the run, solved both ways, agree to
  // the solve's tolerance: Newton stops where its changes stop halving, below 1e-7, at the
  // rounding noise of the map (M and Ṁ·v from residuals; 1e-9 here). The runs themselves
  // part, as the motion is chaotic: 3e-5 after 1 s.
  for (double t = 0.0; t < 1.0; t += 0.1) {
    const State from = t > 0.0 ? run(true, s0, t).first : s0;
    const State one = run(true, from, t + o.initial_step).first;
    const State other = run(false, from, t + o.initial_step).first;
    const double difference = std::max((one.q - other.q).cwiseAbs().maxCoeff(),
                                       (one.qd - other.qd).cwiseAbs().maxCoeff());
    const double size = std::max({1.0, one.q.cwiseAbs().maxCoeff(), one.qd.cwiseAbs().maxCoeff()});
    INFO("t = " << t << ": largest difference of q, qd after one step " << difference);
    CHECK(difference < 1e-8 * size);
  }
}
