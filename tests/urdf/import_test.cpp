// URDF robots imported (model/urdf.hpp) against the same robots written by hand
// with the builder, body by body (R, x, v, w, a, dw, partial velocities) and
// through the equations of motion (M, h) at random states; and the imported
// positions against a direct product of the URDF's 4x4 transforms, written
// here from the file's numbers (Eigen, angle-axis rotations).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>

#include "support/equations_checks.hpp"
#include "urdf/robots_by_hand.hpp"
#include <symdyn/model/urdf.hpp>

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;
using model::Transform;
using namespace symdyn::testing::urdf;

namespace {

constexpr double kTolerance = 1e-12;

std::string robot_path(const std::string& file) {
  return std::string(SYMDYN_URDF_DIR) + "/" + file;
}

// ---- The URDF transforms as numbers: 4x4 products, independent of the builder. ----

using Pose = Eigen::Matrix4d;

Pose pose(double x, double y, double z, double roll = 0, double pitch = 0, double yaw = 0) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  Pose T = Pose::Identity();
  T.block<3, 3>(0, 0) = R;
  T.block<3, 1>(0, 3) = Eigen::Vector3d(x, y, z);
  return T;
}

Pose revolute(Eigen::Vector3d axis, double q) {
  Pose T = Pose::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(q, axis.normalized()).toRotationMatrix();
  return T;
}

Pose prismatic(Eigen::Vector3d axis, double q) {
  Pose T = Pose::Identity();
  T.block<3, 1>(0, 3) = q * axis.normalized();
  return T;
}

// Each body's T0G at the coordinates q, in the model's body order.
using DirectPoses = std::function<std::vector<Pose>(const std::vector<double>&)>;

std::vector<Pose> two_link_arm_poses(const std::vector<double>& q) {
  const Pose l1 = revolute({0, 1, 0}, q[0]);
  const Pose l2 = l1 * pose(0.5, 0, 0) * revolute({0, 1, 0}, q[1]);
  return {l1 * pose(0.25, 0, 0), l2 * pose(0.2, 0, 0)};
}

std::vector<Pose> mobile_base_poses(const std::vector<double>& q) {
  const Pose chassis = prismatic({1, 0, 0}, q[0]) * prismatic({0, 1, 0}, q[1]) * pose(0, 0, 0.1) *
                       revolute({0, 0, 1}, q[2]);
  return {chassis * pose(-0.05, 0, 0.05, 0, 0, 0.3), chassis * pose(-0.25, 0, -0.05),
          chassis * pose(0.1, 0.2, 0, -kHalfPi) * revolute({0, 0, 1}, q[3]),
          chassis * pose(0.1, -0.2, 0) * revolute({0, 1, 0}, q[4])};
}

std::vector<Pose> six_dof_arm_poses(const std::vector<double>& q) {
  const Pose base = pose(0.1, -0.2, 0.05, 0, 0, 0.4);
  const Pose l1 = base * pose(0, 0, 0.1) * revolute({0, 0, 1}, q[0]);
  const Pose l2 = l1 * pose(0, 0, 0.2, 0, 0, 0.5) * revolute({0, 1, 0}, q[1]);
  const Pose l3 = l2 * pose(0.4, 0, 0, 0.2) * revolute({0, 3, 4}, q[2]);
  const Pose l4 = l3 * pose(0.3, 0, 0, 0, 0, -0.3) * revolute({-1, 0, 0}, q[3]);
  const Pose l5 = l4 * pose(0.05, 0, 0, 0.5, 0.1) * revolute({0, 0, 1}, q[4]);
  const Pose l6 = l5 * pose(0.08, 0, 0) * revolute({1, 1, 0}, q[5]);
  const Pose gripper = l6 * pose(0.05, 0, 0, 0, kHalfPi);
  return {base * pose(0, 0, 0.05),
          l1 * pose(0, 0.01, 0.1, 0.1, 0.2, 0.3),
          l2 * pose(0.2, 0, 0.02, 0.3, -0.2, 0.1),
          l3 * pose(0.15, 0.01, 0, 0, 0.25),
          l5 * pose(0.04, 0, 0.01, -0.2, 0, 0.4),
          l6 * pose(0.02, 0.01, 0, 0, 0, 0.7),
          gripper * pose(0, 0, 0.03)};
}

// ---- The comparisons. ----

std::vector<std::string> coordinate_names(const model::Model& m) {
  std::vector<std::string> names;
  for (const auto& c : m.coordinates()) names.push_back(c.q.name());
  return names;
}

std::vector<std::string> body_names(const model::Model& m) {
  std::vector<std::string> names;
  for (const auto& b : m.bodies()) names.push_back(b.name());
  return names;
}

States random_states(std::size_t nq, unsigned seed) {
  std::mt19937 rng(seed);
  States states;
  for (int k = 0; k < 8; ++k) states.push_back(random_state(rng, nq));
  return states;
}

void check_against_hand_written(const model::Model& imported, const model::Model& by_hand) {
  REQUIRE(coordinate_names(imported) == coordinate_names(by_hand));
  REQUIRE(body_names(imported) == body_names(by_hand));
  const model::Kinematics ki = derive_for_test(imported, false, true),
                          kh = derive_for_test(by_hand, false, true);
  const model::Dynamics di = model::derive_dynamics(imported, ki),
                        dh = model::derive_dynamics(by_hand, kh);
  const States states = random_states(imported.coordinates().size(), 7);
  check_kinematics_agree(imported, ki, by_hand, kh, states, kTolerance);
  Gap gap;
  for (const auto& s : states) {
    const Equations a = derived_equations(imported, ki, di, s),
                    b = derived_equations(by_hand, kh, dh, s);
    gap.add(relative_gap(a.M, b.M), "M");
    gap.add(relative_gap(a.h, b.h), "h");
  }
  check_gap(gap, kTolerance);
  // and the imported equations against the direct sums over its bodies
  check_gap(equations_gap(imported, ki, di, states), kTolerance);
}

void check_against_direct_poses(const model::Model& imported, const DirectPoses& direct) {
  const model::Kinematics k = derive_for_test(imported, false, false);
  Gap gap;
  for (const auto& s : random_states(imported.coordinates().size(), 11)) {
    const auto b = bind_state(imported, k, s);
    symbolic::Evaluator<double> eval(b);
    const std::vector<Pose> T = direct(s.q);
    REQUIRE(T.size() == k.bodies.size());
    for (std::size_t i = 0; i < T.size(); ++i) {
      gap.add(relative_gap(eval33(k.bodies[i].R, eval), T[i].block<3, 3>(0, 0)),
              body_place(imported, i, "R"));
      gap.add(relative_gap(eval3(k.bodies[i].x, eval), T[i].block<3, 1>(0, 3)),
              body_place(imported, i, "x"));
    }
  }
  check_gap(gap, kTolerance);
}

}  // namespace

TEST_CASE("URDF two-link arm: the hand-written model and the 4x4 products", "[urdf]") {
  const model::UrdfRobot robot = model::import_urdf_file(robot_path("two_link_arm.urdf"));
  CHECK(robot.model.name() == "two_link_arm");
  check_against_hand_written(robot.model, two_link_arm_by_hand());
  check_against_direct_poses(robot.model, two_link_arm_poses);
}

TEST_CASE("URDF two-link arm on a floating base (UrdfOptions::floating_base)", "[urdf]") {
  model::UrdfOptions options;
  options.floating_base = true;
  const model::UrdfRobot robot = model::import_urdf_file(robot_path("two_link_arm.urdf"), options);
  check_against_hand_written(robot.model, floating_two_link_arm_by_hand());
  REQUIRE(robot.joints.size() == 3);
  CHECK(robot.joints[0].name == "base_link");
  CHECK(robot.joints[0].type == "floating");
  CHECK(robot.joints[0].coordinates.size() == 6);
}

TEST_CASE(
    "URDF mobile base: prismatic and yaw joints through massless links, wheels, a fixed caster",
    "[urdf]") {
  const model::UrdfRobot robot = model::import_urdf_file(robot_path("mobile_base.urdf"));
  check_against_hand_written(robot.model, mobile_base_by_hand());
  check_against_direct_poses(robot.model, mobile_base_poses);
}

TEST_CASE("URDF 6-DOF arm: oblique axes, rotated origins, massless and fixed links", "[urdf]") {
  const model::UrdfRobot robot = model::import_urdf_file(robot_path("six_dof_arm.urdf"));
  check_against_hand_written(robot.model, six_dof_arm_by_hand());
  check_against_direct_poses(robot.model, six_dof_arm_poses);
}

TEST_CASE("URDF joint limits are kept as data, the initial configuration within them", "[urdf]") {
  const model::UrdfRobot robot = model::import_urdf_file(robot_path("six_dof_arm.urdf"));
  std::vector<std::string> names;
  for (const auto& j : robot.joints) names.push_back(j.name);
  // every joint, fixed ones included, depth-first with children in the order of their joints' names
  CHECK(names == std::vector<std::string>{"mount", "joint1", "joint2", "joint3", "joint4", "joint5",
                                          "camera_mount", "joint6", "gripper_mount", "tool_mount"});
  const model::UrdfJoint& j3 = robot.joints[3];
  CHECK(j3.type == "revolute");
  CHECK(j3.coordinates == std::vector<std::string>{"joint3"});
  REQUIRE(j3.limits);
  CHECK(j3.limits->lower == -2.5);
  CHECK(j3.limits->upper == 2.5);
  CHECK(j3.limits->velocity == 3.0);
  CHECK(j3.limits->effort == 80.0);
  const model::UrdfJoint& j6 = robot.joints[7];
  CHECK(j6.type == "continuous");
  REQUIRE(j6.limits);
  CHECK(j6.limits->velocity == 6.0);
  CHECK(robot.joints[0].type == "fixed");
  CHECK(robot.joints[0].coordinates.empty());
  CHECK_FALSE(robot.joints[0].limits);

  // a coordinate whose range excludes 0 starts at its nearest limit
  const std::string lifted = R"(<robot name="lift"><link name="a"/>
    <joint name="lift" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
      <limit lower="0.2" upper="0.5" velocity="1" effort="100"/></joint>
    <link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    </robot>)";
  CHECK(model::import_urdf(lifted).model.coordinates()[0].initial == 0.2);
}

TEST_CASE("URDF gravity is (0, 0, -9.81) unless set", "[urdf]") {
  const auto path = robot_path("two_link_arm.urdf");
  CHECK(model::import_urdf_file(path).model.gravity()[2].number().to_double() == -9.81);
  model::UrdfOptions options;
  options.gravity[0] = 1.0;
  options.gravity[2] = -1.62;
  const model::Model moon = model::import_urdf_file(path, options).model;
  CHECK(moon.gravity()[0].number().to_double() == 1.0);
  CHECK(moon.gravity()[2].number().to_double() == -1.62);
}

TEST_CASE("URDF: the pendulum of docs/urdf.md is the builder model the page says", "[urdf]") {
  using model::Tdisp, model::Troty;
  model::Model m("pendulum");
  const Expr q = m.coordinate("hinge");
  m.body("rod")
      .mass(1)
      .inertia(0.0833, 0.0833, 0.001)
      .motion(Tdisp(0, 0, 1) * Troty(q) * Tdisp(0, 0, -0.5));
  m.gravity(0, 0, -9.81);
  // The page's import, of its robots/pendulum.urdf (tests/docs/urdf_pendulum).
  // options: floating_base = false, gravity = {0, 0, -9.81}, name = the robot's
  symdyn::model::UrdfOptions options;
  const symdyn::model::UrdfRobot robot = symdyn::model::import_urdf_file(PENDULUM_URDF, options);
  // robot.model: a symdyn::model::Model; robot.joints: the joints' types, coordinates and limits
  check_against_hand_written(robot.model, m);
  REQUIRE(robot.joints.size() == 1);
  CHECK(robot.joints[0].type == "continuous");
  CHECK(robot.joints[0].coordinates == std::vector<std::string>{"hinge"});
}

TEST_CASE("URDF: a floating joint gives six coordinates named after it", "[urdf]") {
  const std::string xml = R"(<robot name="drone"><link name="world"/>
    <joint name="free" type="floating"><parent link="world"/><child link="body"/><origin xyz="0 0 1"/></joint>
    <link name="body"><inertial><origin xyz="0.1 0 0" rpy="0 0 0.2"/><mass value="2"/>
      <inertia ixx="0.01" iyy="0.02" izz="0.025" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  const model::UrdfRobot robot = model::import_urdf(xml);
  CHECK(coordinate_names(robot.model) == std::vector<std::string>{"free_x", "free_y", "free_z",
                                                                  "free_yaw", "free_pitch",
                                                                  "free_roll"});
  model::Model by_hand("drone");
  std::vector<Expr> f;
  for (const auto& n : coordinate_names(robot.model)) f.push_back(by_hand.coordinate(n));
  by_hand.body("body")
      .mass(2)
      .inertia(0.01, 0.02, 0.025)
      .motion(model::Tdisp(0, 0, 1) * model::Tdisp(f[0], f[1], f[2]) * model::Trotz(f[3]) *
              model::Troty(f[4]) * model::Trotx(f[5]) * origin(0.1, 0, 0, 0, 0, 0.2));
  by_hand.gravity(0, 0, -9.81);
  check_against_hand_written(robot.model, by_hand);
}

TEST_CASE("URDF: rpy angles are read as written, a pitch near ±90° included", "[urdf]") {
  // urdfdom keeps rpy as a quaternion; its getRPY rounds a pitch within 0.0045
  // rad of ±90° to ±π/2 (1.569 would become 1.5707963...).
  const std::string xml = R"(<robot name="tilted"><link name="world"/>
    <joint name="hinge" type="continuous"><parent link="world"/><child link="rod"/>
      <origin xyz="0 0 1" rpy="0.3 1.569 -0.2"/><axis xyz="0 1 0"/></joint>
    <link name="rod"><inertial><origin xyz="0 0 -0.5" rpy="0.1 -1.5705 0.4"/><mass value="1"/>
      <inertia ixx="0.0833" iyy="0.0833" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  model::Model by_hand("tilted");
  const Expr q = by_hand.coordinate("hinge");
  by_hand.body("rod")
      .mass(1)
      .inertia(0.0833, 0.0833, 0.001)
      .motion(origin(0, 0, 1, 0.3, 1.569, -0.2) * model::Troty(q) *
              origin(0, 0, -0.5, 0.1, -1.5705, 0.4));
  by_hand.gravity(0, 0, -9.81);
  check_against_hand_written(model::import_urdf(xml).model, by_hand);
}

TEST_CASE("URDF: names made identifiers stay unique, the time 't' left to time", "[urdf]") {
  // "a-b" and "a_b" both become a_b, "arm-1" and "arm_1" both arm_1; a joint "t" would be time.
  const std::string xml = R"(<robot name="names"><link name="base"/>
    <joint name="a-b" type="continuous"><parent link="base"/><child link="arm-1"/></joint>
    <joint name="a_b" type="continuous"><parent link="base"/><child link="arm_1"/></joint>
    <joint name="t" type="prismatic"><parent link="base"/><child link="tip"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="arm-1"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="arm_1"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="tip"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    </robot>)";
  const model::UrdfRobot robot = model::import_urdf(xml);
  CHECK(coordinate_names(robot.model) == std::vector<std::string>{"a_b", "a_b_2", "t_2"});
  std::vector<std::string> bodies;
  for (const auto& b : robot.model.bodies()) bodies.push_back(b.name());
  CHECK(bodies == std::vector<std::string>{"arm_1", "arm_1_2", "tip"});
  // Each joint's record names the coordinate it drives, as the model has it.
  REQUIRE(robot.joints.size() == 3);
  CHECK(robot.joints[0].name == "a-b");
  CHECK(robot.joints[0].coordinates == std::vector<std::string>{"a_b"});
  CHECK(robot.joints[1].coordinates == std::vector<std::string>{"a_b_2"});
  CHECK(robot.joints[2].coordinates == std::vector<std::string>{"t_2"});
  // A joint named as an earlier coordinate's rate (hinge_d, of hinge) gets hinge_d_2.
  const std::string rates = R"(<robot name="rates"><link name="base"/>
    <joint name="hinge" type="continuous"><parent link="base"/><child link="b"/></joint>
    <joint name="hinge_d" type="continuous"><parent link="b"/><child link="c"/></joint>
    <link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="c"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    </robot>)";
  CHECK(coordinate_names(model::import_urdf(rates).model) ==
        std::vector<std::string>{"hinge", "hinge_d_2"});
}
