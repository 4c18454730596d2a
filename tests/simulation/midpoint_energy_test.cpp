// The implicit midpoint rule in (q, p) keeps the double pendulum's energy error
// bounded: over 1 000 s of the chaotic swing from the horizontal release, the
// largest energy error in the last 100 s is about that of the first 100 s, while
// rk4 at the same step (not symplectic) drifts in proportion to time.

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "double_pendulum_absolute.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

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
