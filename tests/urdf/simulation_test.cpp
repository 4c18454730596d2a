// The 6-DOF arm generated from its URDF file by symdyn_add_urdf_model, run by
// the runtime: a free swing under gravity keeps its total energy (no force
// element, no damping: the URDF's <dynamics> are not imported).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "urdf_arm_with_payload.hpp"
#include "urdf_six_dof_arm.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

using namespace symdyn::runtime;

TEST_CASE("the generated URDF arm names its coordinates and bodies after the joints and links",
          "[urdf][simulation]") {
  const Model model = Model::from<symdyn_generated::urdf_six_dof_arm>();
  CHECK(model.q_names() ==
        std::vector<std::string>{"joint1", "joint2", "joint3", "joint4", "joint5", "joint6"});
  CHECK(model.body_names() == std::vector<std::string>{"base_link", "link1", "link2", "link3",
                                                       "link5", "link6", "gripper"});
}

TEST_CASE("the generated URDF arm keeps its energy in a free swing", "[urdf][simulation]") {
  MultibodySystem arm(Model::from<symdyn_generated::urdf_six_dof_arm>(), EquationsSource::emitted);
  State s0 = arm.initial_state();
  for (int j = 0; j < s0.qd.size(); ++j) s0.qd(j) = 0.5 + 0.3 * j;  // every joint moving
  IntegratorOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  o.output_interval = 0.01;
  const double e0 = arm.energies(s0).total();
  double largest_error = 0.0, largest_kinetic = 0.0;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const Energies e = arm.energies(s);
    largest_error = std::max(largest_error, std::abs(e.total() - e0));
    largest_kinetic = std::max(largest_kinetic, e.kinetic);
  };
  make_integrator("dop853", o)->integrate(arm, s0, 2.0);
  INFO("largest energy error " << largest_error << " J, largest kinetic energy " << largest_kinetic
                               << " J");
  CHECK(largest_kinetic > 1.0);  // it swung
  CHECK(largest_error < 1e-7 * largest_kinetic);
}

TEST_CASE("a model file extends an imported URDF robot with the builder", "[urdf][simulation]") {
  const Model model = Model::from<symdyn_generated::urdf_arm_with_payload>();
  CHECK(model.q_names() == std::vector<std::string>{"shoulder", "elbow"});
  CHECK(model.body_names() == std::vector<std::string>{"upper_arm", "forearm", "payload"});
  // at rest, arm horizontal: the shoulder torque is the moment of the weights about the shoulder
  MultibodySystem arm(model, EquationsSource::emitted);
  Vector h;
  arm.bias_forces_emitted(arm.initial_state(), h);
  const double weights =
      9.81 * (1.5 * 0.25 + 0.8 * 0.7 + 2.0 * 1.0);  // payload 0.3 beyond the forearm's G
  CHECK(std::abs(std::abs(h(0)) - weights) < 1e-12 * weights);
}
