#pragma once
// The systems of the work-precision and stress runs, as the scenario files of
// models/scenarios set them up (model variant, initial state, force elements),
// built directly so that a timed run is the integration alone. The trike, whose
// scenario has expressions for its steering and drive, runs through
// symdyn::sim::Simulation instead (work_precision.cpp, stress.cpp).
#include <memory>

#include "double_pendulum_absolute.hpp"
#include "robot3d_absolute.hpp"
#include "slider_crank_inline.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::bench {

struct ProblemSystem {
  std::unique_ptr<runtime::MultibodySystem> system;
  runtime::State initial;
};

template <class Generated>
ProblemSystem make_problem_system() {
  ProblemSystem p{std::make_unique<runtime::MultibodySystem>(runtime::Model::from<Generated>(),
                                                             runtime::EquationsSource::emitted),
                  {}};
  p.initial = p.system->initial_state();
  return p;
}

// models/scenarios/double_pendulum.json: released horizontal at rest (the model's own state).
inline ProblemSystem double_pendulum_problem() {
  return make_problem_system<symdyn_generated::double_pendulum_absolute>();
}

// models/scenarios/slider_crank.json: the crank spun at 50 rad/s from q0 = 0, free motion.
inline ProblemSystem slider_crank_problem() {
  ProblemSystem p = make_problem_system<symdyn_generated::slider_crank_inline>();
  p.initial.q(0) = 0.0;
  p.initial.qd(0) = 50.0;
  return p;
}

// models/scenarios/robot3d.json: thrown from q = (0, 0.3, 0.6, 0, 0) with the turret and
// the wrist spinning, a spring-damper on the arm extension (arm_extension).
inline ProblemSystem robot3d_problem() {
  ProblemSystem p = make_problem_system<symdyn_generated::robot3d_absolute>();
  p.system->add<runtime::CoordinateSpringDamper>("arm_extension", 2, 1000.0, 20.0, 0.6);
  p.initial.q << 0.0, 0.3, 0.6, 0.0, 0.0;
  p.initial.qd << 1.0, 0.0, 0.0, 2.0, 0.0;
  return p;
}

}  // namespace symdyn::bench
