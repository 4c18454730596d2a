#include "pendulum.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

int main() {
  using namespace symdyn::runtime;
  MultibodySystem pendulum(Model::from<symdyn_generated::pendulum>());
  State s = pendulum.initial_state();
  s.q(pendulum.model().coordinate_index("hinge")) = 0.5;
  const State end = make_integrator("dopri5")->integrate(pendulum, s, 10.0);
  return end.q.allFinite() ? 0 : 1;
}
