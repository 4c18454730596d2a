// A URDF robot's <visual> elements placed on its bodies (model::urdf_visuals):
// each pose against the chain of origins composed by hand with Eigen, the
// colours of inline and named materials, package:// mesh paths, and what is
// left out.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <numbers>

#include <symdyn/model/urdf.hpp>

namespace {

using Catch::Matchers::Contains;
using symdyn::model::UrdfVisual;

const char* const kRobot = R"(<robot name="viz">
  <material name="steel"><color rgba="0.5 0.5 0.6 1"/></material>
  <link name="base">
    <inertial><origin xyz="0 0 0.1"/><mass value="2"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.3 0.1"/></geometry>
      <material name="steel"/></visual>
  </link>
  <joint name="j1" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/></joint>
  <link name="arm">
    <inertial><origin xyz="0.25 0 0" rpy="0 0.3 0"/><mass value="1"/>
      <inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.02" length="0.5"/></geometry>
      <material name="red"><color rgba="1 0 0 1"/></material></visual>
  </link>
  <joint name="tool_mount" type="fixed"><parent link="arm"/><child link="tool"/>
    <origin xyz="0.5 0 0" rpy="0.2 0 0"/></joint>
  <link name="tool">
    <visual><origin xyz="0.01 0 0"/><geometry><sphere radius="0.03"/></geometry></visual>
    <visual><geometry><mesh filename="package://viz_robot/meshes/gripper.stl"
      scale="0.001 0.002 0.001"/></geometry></visual>
  </link>
  <joint name="j2" type="continuous"><parent link="base"/><child link="spinner_frame"/>
    <axis xyz="0 0 1"/></joint>
  <link name="spinner_frame">
    <visual><geometry><sphere radius="0.01"/></geometry></visual>
  </link>
  <joint name="spinner_mount" type="fixed"><parent link="spinner_frame"/><child link="spinner"/></joint>
  <link name="spinner">
    <inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
</robot>)";

Eigen::Isometry3d pose(const Eigen::Vector3d& xyz, double roll, double pitch, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = xyz;
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return p;
}

Eigen::Isometry3d pose_of(const UrdfVisual& v) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(v.origin[0], v.origin[1], v.origin[2]);
  p.linear() = Eigen::Map<const Eigen::Matrix3d>(v.axes.data());  // column-major: the axes
  return p;
}

bool same_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).norm() < 1e-12;
}

}  // namespace

TEST_CASE("URDF visuals: placed on their bodies, coloured, meshes resolved", "[urdf]") {
  std::vector<std::string> skipped;
  const auto visuals = symdyn::model::urdf_visuals(kRobot, "/robots/viz_robot/urdf", &skipped);
  REQUIRE(visuals.size() == 4);
  const auto find = [&](const std::string& type) {
    for (const UrdfVisual& v : visuals)
      if (v.type == type) return v;
    FAIL("no " << type);
    return UrdfVisual{};
  };
  // Body frames at G with the inertial axes: visual pose = inertial⁻¹ · (fixed joints) · visual.
  const UrdfVisual box = find("box");
  CHECK(box.body == "base");
  CHECK(box.size == std::array<double, 3>{0.2, 0.3, 0.1});
  CHECK(same_pose(pose_of(box), pose({0, 0, -0.05}, 0, 0, 0)));
  REQUIRE(box.rgba);
  CHECK(*box.rgba == std::array<double, 4>{0.5, 0.5, 0.6, 1});  // the named material

  const Eigen::Isometry3d arm_inertial = pose({0.25, 0, 0}, 0, 0.3, 0);
  const UrdfVisual rod = find("cylinder");
  CHECK(rod.body == "arm");
  CHECK(same_pose(pose_of(rod),
                  arm_inertial.inverse() * pose({0.25, 0, 0}, 0, std::numbers::pi / 2, 0)));
  CHECK(*rod.rgba == std::array<double, 4>{1, 0, 0, 1});

  // The massless tool hangs on the arm through its fixed joint.
  const Eigen::Isometry3d tool = arm_inertial.inverse() * pose({0.5, 0, 0}, 0.2, 0, 0);
  const UrdfVisual ball = find("sphere");
  CHECK(ball.body == "arm");
  CHECK(ball.size[0] == 0.03);
  CHECK(same_pose(pose_of(ball), tool * pose({0.01, 0, 0}, 0, 0, 0)));
  CHECK_FALSE(ball.rgba);
  const UrdfVisual mesh = find("mesh");
  CHECK(mesh.body == "arm");
  CHECK(same_pose(pose_of(mesh), tool));
  CHECK(mesh.mesh == "/robots/viz_robot/meshes/gripper.stl");
  CHECK(mesh.scale == std::array<double, 3>{0.001, 0.002, 0.001});

  // A massless link moved by a joint, before its body: no rigid place to draw it.
  REQUIRE(skipped.size() == 1);
  CHECK_THAT(skipped[0], Contains("spinner_frame"));
}
