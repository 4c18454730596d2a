// URDF inputs symdyn refuses, one case each, with the culprit named.
#include <catch2/catch.hpp>

#include <string>

#include <symdyn/model/urdf.hpp>

using namespace symdyn;
using Catch::Matchers::Contains;

namespace {

const char* const kLink = R"(<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>)";

// A robot of two links, "a" (massless root) and "b" (massive unless `massive_b` is false), joined by `joint`.
std::string robot(const std::string& joint, bool massive_b = true) {
  return std::string(R"(<robot name="r"><link name="a"/><link name="b">)") + (massive_b ? kLink : "") + "</link>" +
         joint + "</robot>";
}

std::string joint(const std::string& name, const std::string& type, const std::string& inside = "") {
  return R"(<joint name=")" + name + R"(" type=")" + type + R"("><parent link="a"/><child link="b"/>)" + inside +
         "</joint>";
}

const std::string kLimit = R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)";

}  // namespace

TEST_CASE("URDF: a planar joint is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("slide_plane", "planar", R"(<axis xyz="0 0 1"/>)"))),
                    Contains("joint 'slide_plane'") && Contains("planar joints are not supported"));
}

TEST_CASE("URDF: a mimic joint is refused, naming it and the joint it mimics", "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="b">)" + std::string(kLink) +
                          R"(</link><link name="c">)" + kLink + R"(</link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
    <joint name="finger" type="continuous"><parent link="b"/><child link="c"/><mimic joint="j1" multiplier="2"/></joint>
    </robot>)";
  CHECK_THROWS_WITH(model::import_urdf(xml), Contains("joint 'finger'") && Contains("mimic") && Contains("'j1'"));
}

TEST_CASE("URDF: an axis of zero length is refused, naming the joint", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("wrist", "revolute", R"(<axis xyz="0 0 0"/>)" + kLimit))),
                    Contains("joint 'wrist'") && Contains("axis"));
}

TEST_CASE("URDF: a missing file is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf_file("/nonexistent/arm.urdf"),
                    Contains("'/nonexistent/arm.urdf'") && Contains("cannot be read"));
}

TEST_CASE("URDF: urdfdom's parse errors are passed on", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf("<robot name=\"r\"><link name=\"a\"/>"), Contains("URDF"));
  // a revolute joint without its required <limit>: urdfdom's own message
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("elbow", "revolute"))), Contains("URDF") && Contains("elbow"));
}

TEST_CASE("URDF: a movable joint with no mass beyond it is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("spin", "continuous"), false)),
                    Contains("joint 'spin'") && Contains("moves no body") && Contains("link 'b'"));
}

TEST_CASE("URDF: a non-physical inertia is refused by the builder's checks, naming the body", "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="flat">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.5" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="flat"/></joint></robot>)";
  const model::UrdfRobot robot = model::import_urdf(xml);  // the inertia is checked with the whole model
  CHECK_THROWS_WITH(robot.model.validate(), Contains("body 'flat'"));
}

TEST_CASE("URDF: a negative mass is refused by the builder's checks, naming the body", "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="ghost">
    <inertial><mass value="-1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="ghost"/></joint></robot>)";
  CHECK_THROWS_WITH(model::import_urdf(xml).model.validate(), Contains("body 'ghost'"));
}

TEST_CASE("URDF: closed loops are refused", "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="b">)" + std::string(kLink) +
                          R"(</link><link name="c">)" + kLink + R"(</link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
    <joint name="j2" type="continuous"><parent link="b"/><child link="c"/></joint>
    <joint name="j3" type="continuous"><parent link="c"/><child link="b"/></joint>
    </robot>)";
  CHECK_THROWS_WITH(model::import_urdf(xml), Contains("URDF") && Contains("'b'"));
}
