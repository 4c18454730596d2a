// Simulates the spinning top (spinning_top.cpp) from steady precession and checks
// the motion against the closed form: the nutation stays at its initial value,
// the precession angle grows at the steady rate, and the energy and the vertical
// angular momentum about the tip are conserved. Exits 1 when a check fails.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "spinning_top.hpp"  // emitted by symdyn_add_model
#include "spinning_top_parameters.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/runtime.hpp>

using namespace symdyn::runtime;

namespace {

constexpr double kDuration = 5.0;  // s, about two turns of precession

struct Check {
  const char* what;
  double error;
  double tolerance;
};

bool report(const Check& c) {
  const bool ok = c.error <= c.tolerance;
  fmt::print("{:<44} {:.3e} (tolerance {:.0e}) {}\n", c.what, c.error, c.tolerance,
             ok ? "ok" : "FAILED");
  return ok;
}

}  // namespace

int main() {
  MultibodySystem system(Model::from<symdyn_generated::spinning_top>());
  const State start = system.initial_state();
  const double energy0 = system.energies(start).total();
  const double momentum0 = system.momentum(start).angular.z();

  double max_nutation_error = 0.0;
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-10;
  options.output_interval = 0.01;
  options.on_output = [&](const State& s, const Vector&, const Vector&) {
    max_nutation_error = std::max(max_nutation_error, std::abs(s.q(1) - spinning_top::kNutation));
  };
  auto integrator = make_integrator("dopri5", options);
  const State end = integrator->integrate(system, start, kDuration);

  const double precession = spinning_top::steady_precession_rate();
  fmt::print("spinning top: steady precession at {:.6f} rad/s, {} s in {} steps\n", precession,
             kDuration, integrator->statistics().steps);
  const Check checks[] = {
      {"max |theta - theta0| (rad)", max_nutation_error, 1e-8},
      {"|psi(T) - W T| (rad)", std::abs(end.q(0) - precession * kDuration), 1e-8},
      {"|E(T) - E(0)| / |E(0)|",
       std::abs(system.energies(end).total() - energy0) / std::abs(energy0), 1e-10},
      {"|Lz(T) - Lz(0)| / |Lz(0)|",
       std::abs(system.momentum(end).angular.z() - momentum0) / std::abs(momentum0), 1e-10},
  };
  bool ok = true;
  for (const Check& c : checks) ok = report(c) && ok;
  return ok ? 0 : 1;
}
