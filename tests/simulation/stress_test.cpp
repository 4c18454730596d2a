// The quick stress cases of bench/stress/stress.cpp (bench/results/stress.md), each
// checked against something independent of the integrator under test: a second
// integrator, a conservation law, or the expected failure message.
//
//   chaos  the double pendulum from its horizontal release: dop853 and dopri5 at
//          1e-13 agree within 1e-6 over the first 8 s (they part by 1e-6 near 12 s),
//          and, the motion being chaotic, by more than 1e-2 before 40 s;
//   spin   robot3d with its wrist at 1e4 rad/s: energy and the angular momentum
//          about the turret axis (z; gravity has no moment about it) stay;
//   trike  the stiff tyres: rk4 at h = 1/30 s fails naming the time and the wheel,
//          cvode at 1e-6 follows dop853 at 1e-11.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../../bench/work_precision/problems.hpp"
#include "robot3d_absolute.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;

using ScenarioSystem = symdyn::bench::ProblemSystem;

IntegratorOptions tolerance(double tol) {
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = tol;
  return o;
}

double max_difference(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

std::vector<State> trajectory(ScenarioSystem& s, const char* integrator, double tol, double t_end) {
  std::vector<State> out;
  IntegratorOptions o = tolerance(tol);
  o.output_interval = 0.01;
  o.on_output = [&](const State& x, const Vector&, const Vector&) { out.push_back(x); };
  make_integrator(integrator, o)->integrate(*s.system, s.initial, t_end);
  return out;
}

}  // namespace

TEST_CASE("chaotic double pendulum: two tight integrators agree, then part", "[stress]") {
  ScenarioSystem s = symdyn::bench::double_pendulum_problem();
  const std::vector<State> a = trajectory(s, "dop853", 1e-13, 40.0),
                           b = trajectory(s, "dopri5", 1e-13, 40.0);
  REQUIRE(a.size() == b.size());
  double parted = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double d = max_difference(a[k], b[k]);
    INFO(fmt::format("t = {}: dop853 and dopri5 at 1e-13 differ by {:.3g}", a[k].t, d));
    if (a[k].t <= 8.0) REQUIRE(d < 1e-6);
    parted = std::max(parted, d);
  }
  CHECK(parted > 1e-2);
}

TEST_CASE("robot3d spun at 1e4 rad/s keeps its energy and its angular momentum about z",
          "[stress]") {
  MultibodySystem sys(Model::from<symdyn_generated::robot3d_absolute>(), EquationsSource::emitted);
  State x0 = sys.initial_state();
  x0.q << 0.0, 0.3, 0.6, 0.0, 0.2;
  x0.qd << 1.0, 0.0, 0.0, 1e4, 0.0;  // the wrist spins
  const double e0 = sys.energies(x0).total(), lz0 = sys.momentum(x0).angular.z();
  const double l_scale = sys.momentum(x0).angular.norm();
  double de = 0.0, dl = 0.0;
  IntegratorOptions o = tolerance(1e-12);
  o.output_interval = 1e-3;
  o.on_output = [&](const State& x, const Vector&, const Vector&) {
    de = std::max(de, std::abs(sys.energies(x).total() - e0) / std::abs(e0));
    dl = std::max(dl, std::abs(sys.momentum(x).angular.z() - lz0) / l_scale);
  };
  make_integrator("dop853", o)->integrate(sys, x0, 0.2);
  INFO(fmt::format("relative energy error {:.3g}, L_z error / |L0| {:.3g}", de, dl));
  CHECK(de < 1e-9);
  CHECK(dl < 1e-7);
}

// Beyond the tyres' stability limit rk4 diverges (q ~ 1e65, qd ~ 1e124 at the
// step that fails): which value overflows first, a tyre's force or a bias
// force (whose emitted arithmetic is that of the normal form of
// symbolic/trig_polynomial.hpp), is an accident of rounding; the error names
// the time and the one it met.
TEST_CASE(
    "trike's stiff tyres: rk4 at a large step fails naming time and what overflowed, cvode follows "
    "dop853",
    "[stress]") {
  const auto run_trike = [](const char* integrator, double tolerance, double step, double t_end) {
    symdyn::sim::RunOptions o;
    o.t_end = t_end;
    o.integrator = integrator;
    o.output_interval = t_end;
    if (step > 0.0)
      o.step = step;
    else
      o.tolerance = tolerance;
    symdyn::sim::Simulation sim(symdyn::sim::find_builtin("trike"), o);
    return sim.run().final;
  };
  try {
    run_trike("rk4", 0.0, 1.0 / 30.0, 1.0);
    FAIL("rk4 at h = 1/30 s crossed the tyres' stability limit without an error");
  } catch (const NumericError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("t = ") != std::string::npos);
    // The step that fails has grown q and qd past 1e100: whether a tyre's force
    // or the bias forces overflow first there depends on the rounding of the
    // states before it (the recursive forward dynamics or M's Cholesky).
    CHECK((what.find("wheel") != std::string::npos ||
           what.find("bias force on coordinate") != std::string::npos));
  }
  CHECK(max_difference(run_trike("cvode", 1e-6, 0.0, 2.0), run_trike("dop853", 1e-11, 0.0, 2.0)) <
        1e-3);
}
