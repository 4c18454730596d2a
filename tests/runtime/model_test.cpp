#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/pendulum.hpp"
#include "fixtures/rigid_body.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/multibody_system.hpp>

using namespace symdyn::runtime;
using Catch::Matchers::Contains;
namespace fx = symdyn_fixtures;

TEST_CASE("Model::from reads names, sizes, initial state and gravity", "[runtime][model]") {
  const Model m = Model::from<fx::double_pendulum_absolute>();
  CHECK(m.name() == "double_pendulum");
  CHECK(m.variant() == "absolute");
  CHECK(m.nq() == 2);
  CHECK(m.nbody() == 2);
  CHECK(m.nparam() == 0);
  CHECK(m.q_names() == std::vector<std::string>{"q0", "q1"});
  CHECK(m.body_names() == std::vector<std::string>{"rod1", "rod2"});
  CHECK(m.body_index("rod2") == 1);
  CHECK(m.coordinate_index("q1") == 1);
  CHECK(m.gravity() == Vec3(0.0, -9.81, 0.0));
  CHECK(m.mass(1) == 1.0);
  CHECK(m.inertia(0)(2, 2) == Approx(1.0 / 12.0));
  CHECK(m.reference_body(1) == -1);
  const State s = m.initial_state();
  CHECK(s.q == Vector::Zero(2));
  CHECK(s.qd == Vector::Zero(2));
}

TEST_CASE("Model::from detects the entry points present", "[runtime][model]") {
  const Model dp = Model::from<fx::double_pendulum_absolute>();
  CHECK(dp.has_positions());
  CHECK(dp.has_equations_of_motion());
  const Model p = Model::from<fx::pendulum>();
  CHECK_FALSE(p.has_equations_of_motion());
  const Model rb = Model::from<fx::rigid_body>();
  CHECK_FALSE(rb.has_positions());
  CHECK(rb.has_velocities());
  const Model sl = Model::from<fx::slider<0>>();
  CHECK(sl.has_positions());
  CHECK_FALSE(sl.has_velocities());
  CHECK_FALSE(sl.has_partial_velocities());
  CHECK(sl.variant().empty());
}

TEST_CASE("Absent entry points and unknown names are ModelErrors naming them",
          "[runtime][model][errors]") {
  const Model sl = Model::from<fx::slider<0>>();
  Kinematics k = sl.make_kinematics();
  const double q = 0.5, qd = 1.0;
  sl.positions(0.0, &q, k);
  CHECK(k.x(0)(0) == 0.5);
  CHECK_THROWS_MATCHES(
      sl.velocities(0.0, &q, &qd, k), ModelError,
      Catch::Matchers::Message(
          "model 'slider' (variant ''): entry point 'velocities' was not emitted"));
  CHECK_THROWS_WITH(MultibodySystem(sl), Contains("needs the entry point 'velocities'"));
  CHECK_THROWS_WITH(sl.body_index("wheel"), "model 'slider': no body named 'wheel' (bodies: puck)");
  CHECK_THROWS_WITH(sl.coordinate_index("x"),
                    "model 'slider': no coordinate named 'x' (coordinates: s)");
  const Model p = Model::from<fx::pendulum>();
  CHECK_THROWS_WITH(MultibodySystem(p, EquationsSource::emitted),
                    Contains("the emitted source needs mass_matrix and bias_forces"));
}

TEST_CASE("Inertia is validated at construction, naming the body", "[runtime][model][errors]") {
  CHECK_NOTHROW(Model::from<fx::slider<0>>());
  CHECK_THROWS_MATCHES(Model::from<fx::slider<1>>(), ModelError,
                       Catch::Matchers::Message("body 'puck': mass -1 is not positive"));
  CHECK_THROWS_WITH(Model::from<fx::slider<2>>(),
                    "body 'puck': inertia is not positive definite (principal moments -1, 1, 1)");
  CHECK_THROWS_WITH(
      Model::from<fx::slider<3>>(),
      "body 'puck': inertia violates the triangle inequality (principal moments 1 + 1 < 3)");
  CHECK_THROWS_WITH(Model::from<fx::slider<4>>(),
                    Contains("body 'puck': inertia is not symmetric"));
}

TEST_CASE("Parameters are settable and re-validate the inertia", "[runtime][model]") {
  Model m = Model::from<fx::pendulum>();
  REQUIRE(m.parameters().size() == 1);
  CHECK(m.parameters()[0] == 1.0);
  m.set_parameter("length", 2.0);
  CHECK(m.inertia(0)(2, 2) == Approx(4.0 / 12.0));
  // The kinematics follow the parameter.
  Kinematics k = m.make_kinematics();
  const double q = 0.0;
  m.positions(0.0, &q, k);
  CHECK(k.x(0)(0) == Approx(1.0));
  CHECK_THROWS_WITH(m.set_parameter("mass", 1.0),
                    "model 'pendulum': no parameter named 'mass' (parameters: length)");
  CHECK_THROWS_WITH(m.set_parameter("length", 0.0),
                    Contains("body 'rod': inertia is not positive definite"));
  CHECK(m.parameters()[0] == 2.0);  // unchanged by the failed update
  CHECK_THROWS_WITH(m.set_parameters({1.0, 2.0}),
                    "model 'pendulum': 2 parameter values given, expected 1");
  CHECK_THROWS_WITH(m.set_parameter("length", std::numeric_limits<double>::quiet_NaN()),
                    "model 'pendulum': parameter 'length' must be finite, not nan");
  CHECK_THROWS_WITH(m.set_parameter("length", -std::numeric_limits<double>::infinity()),
                    "model 'pendulum': parameter 'length' must be finite, not -inf");
  CHECK(m.parameters()[0] == 2.0);
}

TEST_CASE("Kinematics views and point helpers", "[runtime][model]") {
  const Model m = Model::from<fx::double_pendulum_absolute>();
  Kinematics k = m.make_kinematics();
  const double q[2] = {0.4, -0.9}, qd[2] = {1.3, 0.7};
  m.velocities(0.0, q, qd, k);
  m.partial_velocities(0.0, q, k);
  // The tip of rod 2 is at (l2/2, 0, 0) in its body coordinates.
  const Vec3 tip(std::cos(q[0]) + std::cos(q[0] + q[1]), std::sin(q[0]) + std::sin(q[0] + q[1]), 0);
  CHECK((k.point_position(1, Vec3(0.5, 0, 0)) - tip).norm() < 1e-15);
  const Vec3 vtip(-std::sin(q[0]) * qd[0] - std::sin(q[0] + q[1]) * (qd[0] + qd[1]),
                  std::cos(q[0]) * qd[0] + std::cos(q[0] + q[1]) * (qd[0] + qd[1]), 0);
  CHECK((k.point_velocity(1, Vec3(0.5, 0, 0)) - vtip).norm() < 1e-14);
  CHECK((k.velocity_at(1, tip) - vtip).norm() < 1e-14);
  CHECK(k.point_position(ground, Vec3(1, 2, 3)) == Vec3(1, 2, 3));
  CHECK(k.point_velocity(ground, Vec3(1, 2, 3)) == Vec3::Zero());
  CHECK(k.dv_dqd(1, 1) == k.dv_dqd(1).row(1).transpose());
  CHECK(k.w(1)(2) == Approx(qd[0] + qd[1]));
}

TEST_CASE("Kinematics::all_finite sees a non-finite value in any array it checks",
          "[runtime][model]") {
  const Model m = Model::from<fx::double_pendulum_absolute>();
  Kinematics k = m.make_kinematics();
  const double q[2] = {0.4, -0.9}, qd[2] = {1.3, 0.7}, qdd[2] = {0.2, -0.1};
  m.accelerations(0.0, q, qd, qdd, k);
  m.partial_velocities(0.0, q, k);
  CHECK(k.all_finite(true));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto with = [&](double* array, std::size_t at, double value, bool accelerations) {
    const double kept = array[at];
    array[at] = value;
    const bool finite = k.all_finite(accelerations);
    array[at] = kept;
    return finite;
  };
  CHECK_FALSE(with(k.R_data(), 17, nan, false));
  CHECK_FALSE(with(k.x_data(), 5, -INFINITY, false));
  CHECK_FALSE(with(k.v_data(), 0, nan, false));
  CHECK_FALSE(with(k.w_data(), 3, nan, false));
  CHECK_FALSE(with(k.dv_dqd_data(), 11, nan, false));
  CHECK_FALSE(with(k.dw_dqd_data(), 6, INFINITY, false));
  // Accelerations count only when asked for.
  CHECK(with(k.a_data(), 4, nan, false));
  CHECK_FALSE(with(k.a_data(), 4, nan, true));
  CHECK_FALSE(with(k.dw_data(), 2, nan, true));
}
