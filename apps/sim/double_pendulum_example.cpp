// The smallest simulation on generated code, quoted in README.md: the double
// pendulum of docs/models.md, free for 10 s, as symdyn-sim runs it (same model,
// integrator and tolerance), CSV on stdout.
#include <fmt/format.h>

#include <iostream>

#include "double_pendulum_absolute.hpp"  // emitted by symdyn_add_model
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/runtime.hpp>

using namespace symdyn::runtime;

int main() {
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
  CsvRecorder csv(std::cout, system);

  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-10;
  options.output_interval = 0.01;
  options.on_output = [&](const State& s, const Vector&, const Vector&) { csv.write(s); };
  auto integrator = make_integrator("dopri5", options);
  const State end = integrator->integrate(system, system.initial_state(), 10.0);

  fmt::print(stderr, "q = ({:.6f}, {:.6f}) at t = {}, {} steps, energy {:.3g} J\n", end.q(0),
             end.q(1), end.t, integrator->statistics().steps, system.energies(end).total());
}
