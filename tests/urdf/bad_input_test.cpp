// URDF inputs symdyn refuses, one case each, with the culprit named.
#include <catch2/catch.hpp>
#include <string>

#include <symdyn/model/urdf.hpp>
#include <symdyn/symbolic/eval.hpp>

using namespace symdyn;
using Catch::Matchers::Contains;

namespace {

const char* const kLink =
    R"(<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>)";

// A robot of two links, "a" (massless root) and "b" (massive unless `massive_b` is false), joined
// by `joint`.
std::string robot(const std::string& joint, bool massive_b = true) {
  return std::string(R"(<robot name="r"><link name="a"/><link name="b">)") +
         (massive_b ? kLink : "") + "</link>" + joint + "</robot>";
}

std::string joint(const std::string& name, const std::string& type,
                  const std::string& inside = "") {
  return R"(<joint name=")" + name + R"(" type=")" + type +
         R"("><parent link="a"/><child link="b"/>)" + inside + "</joint>";
}

const std::string kLimit = R"(<limit lower="-1" upper="1" velocity="1" effort="1"/>)";

}  // namespace

TEST_CASE("URDF: a planar joint is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(
      model::import_urdf(robot(joint("slide_plane", "planar", R"(<axis xyz="0 0 1"/>)"))),
      Contains("joint 'slide_plane'") && Contains("planar joints are not supported"));
}

// Links a (root), b, c: j1 from a to b, `second` from b to c.
std::string two_joints(const std::string& second) {
  return R"(<robot name="r"><link name="a"/><link name="b">)" + std::string(kLink) +
         R"(</link><link name="c">)" + kLink + R"(</link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>)" +
         second + "</robot>";
}

TEST_CASE("URDF: a mimic joint is the dependent parameter multiplier·q + offset", "[urdf][mimic]") {
  const model::UrdfRobot r = model::import_urdf(two_joints(
      R"(<joint name="finger" type="continuous"><parent link="b"/><child link="c"/>
         <mimic joint="j1" multiplier="2" offset="0.5"/></joint>)"));
  REQUIRE(r.model.coordinates().size() == 1);
  REQUIRE(r.model.dependents().size() == 1);
  const model::Dependent& finger = r.model.dependents()[0];
  CHECK(finger.symbol.name() == "finger");
  const model::Expr q = r.model.coordinates()[0].q;
  symbolic::Bindings<double> at{{q, 0.3}};
  symbolic::Evaluator<double> evaluate(at);
  CHECK(evaluate(finger.expression) == Approx(2 * 0.3 + 0.5).epsilon(1e-15));
  REQUIRE(r.joints.size() == 2);
  CHECK(r.joints[1].mimic == "j1");
  CHECK(r.joints[1].coordinates.empty());
  CHECK_NOTHROW(r.model.validate());
}

TEST_CASE("URDF: a mimic joint of a joint met after it, or of a fixed joint, is refused",
          "[urdf][errors]") {
  CHECK_THROWS_WITH(
      model::import_urdf(two_joints(
          R"(<joint name="finger" type="continuous"><parent link="b"/><child link="c"/>
             <mimic joint="thumb"/></joint>)")),
      Contains("URDF joint 'finger' mimics 'thumb', which is not a revolute, continuous or "
               "prismatic joint met before it"));
  CHECK_THROWS_WITH(model::import_urdf(two_joints(
                        R"(<joint name="clamp" type="fixed"><parent link="b"/><child link="c"/>
             <mimic joint="j1"/></joint>)")),
                    Contains("URDF joint 'clamp': a fixed joint cannot mimic 'j1'"));
}

TEST_CASE("URDF: an axis of zero length is refused, naming the joint", "[urdf][errors]") {
  CHECK_THROWS_WITH(
      model::import_urdf(robot(joint("wrist", "revolute", R"(<axis xyz="0 0 0"/>)" + kLimit))),
      Contains("joint 'wrist'") && Contains("axis"));
}

TEST_CASE("URDF: a missing file is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf_file("/nonexistent/arm.urdf"),
                    Contains("'/nonexistent/arm.urdf'") && Contains("cannot be read"));
}

TEST_CASE("URDF: urdfdom's parse errors are passed on", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf("<robot name=\"r\"><link name=\"a\"/>"), Contains("URDF"));
  // a revolute joint without its required <limit>: urdfdom's own message
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("elbow", "revolute"))),
                    Contains("URDF") && Contains("elbow"));
}

TEST_CASE("URDF: a movable joint with no mass beyond it is refused, naming it", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::import_urdf(robot(joint("spin", "continuous"), false)),
                    Contains("joint 'spin'") && Contains("moves no body") && Contains("link 'b'"));
}

TEST_CASE("URDF: a non-physical inertia is refused by the builder's checks, naming the body",
          "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="flat">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.5" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="flat"/></joint></robot>)";
  const model::UrdfRobot robot =
      model::import_urdf(xml);  // the inertia is checked with the whole model
  CHECK_THROWS_WITH(robot.model.validate(), Contains("body 'flat'"));
}

TEST_CASE("URDF: a negative mass is refused by the builder's checks, naming the body",
          "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="ghost">
    <inertial><mass value="-1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="ghost"/></joint></robot>)";
  CHECK_THROWS_WITH(model::import_urdf(xml).model.validate(), Contains("body 'ghost'"));
}

TEST_CASE("URDF: closed loops are refused", "[urdf][errors]") {
  const std::string xml = R"(<robot name="r"><link name="a"/><link name="b">)" +
                          std::string(kLink) + R"(</link><link name="c">)" + kLink + R"(</link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
    <joint name="j2" type="continuous"><parent link="b"/><child link="c"/></joint>
    <joint name="j3" type="continuous"><parent link="c"/><child link="b"/></joint>
    </robot>)";
  CHECK_THROWS_WITH(model::import_urdf(xml), Contains("URDF") && Contains("'b'"));
}

namespace {

// A robot whose link "b" has the given <inertial> and whose joint "j" the given inside.
std::string robot_with(const std::string& inertial, const std::string& inside) {
  return R"(<robot name="r"><link name="a"/><link name="b">)" + inertial + "</link>" +
         joint("j", "revolute", inside) + "</robot>";
}

std::string inertial(const std::string& mass, const std::string& ixx = "0.1",
                     const std::string& origin = "") {
  return "<inertial>" + origin + R"(<mass value=")" + mass + R"("/><inertia ixx=")" + ixx +
         R"(" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>)";
}

const std::string kAxisAndLimit = R"(<axis xyz="0 0 1"/>)" + kLimit;

}  // namespace

TEST_CASE(
    "URDF: numbers that are not finite are refused, naming the link or joint and the attribute",
    "[urdf][errors]") {
  struct Case {
    std::string xml, culprit;
  };
  const Case cases[] = {
      // urdfdom logged these and kept the link with mass 0 (a massless frame) or inertia 0.
      {robot_with(inertial("nan"), kAxisAndLimit),
       R"(URDF link 'b': <inertial><mass value="nan">: 'nan' is not a finite number)"},
      {robot_with(inertial("1", "inf"), kAxisAndLimit),
       R"(URDF link 'b': <inertial><inertia ixx="inf">: 'inf' is not a finite number)"},
      {robot_with(inertial("1e400"), kAxisAndLimit),
       R"(URDF link 'b': <inertial><mass value="1e400">: '1e400' is beyond the range of a double)"},
      // 1e-400 reads as 0: a link silently massless.
      {robot_with(inertial("1e-400"), kAxisAndLimit),
       R"(URDF link 'b': <inertial><mass value="1e-400">: '1e-400' is beyond)"},
      {robot_with(inertial("1", "0.1", R"(<origin xyz="0 0 0" rpy="0 NaN 0"/>)"), kAxisAndLimit),
       R"(URDF link 'b': <inertial><origin rpy="0 NaN 0">: 'NaN' is not a finite number)"},
      {robot_with(inertial("1"), R"(<origin xyz="0 1e999 0"/>)" + kAxisAndLimit),
       R"(URDF joint 'j': <origin xyz="0 1e999 0">: '1e999' is beyond the range of a double)"},
      {robot_with(inertial("1"), R"(<origin rpy="-inf 0 0"/>)" + kAxisAndLimit),
       R"(URDF joint 'j': <origin rpy="-inf 0 0">: '-inf' is not a finite number)"},
      {robot_with(inertial("1"), R"(<axis xyz="0 0 nan"/>)" + kLimit),
       R"(URDF joint 'j': <axis xyz="0 0 nan">: 'nan' is not a finite number)"},
      {robot_with(inertial("1"),
                  R"(<axis xyz="0 0 1"/><limit lower="-inf" upper="1" velocity="1" effort="1"/>)"),
       R"(URDF joint 'j': <limit lower="-inf">: '-inf' is not a finite number)"},
      {robot_with(inertial("1"),
                  R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="nan" effort="1"/>)"),
       R"(URDF joint 'j': <limit velocity="nan">)"},
      {robot_with(inertial("1"), kAxisAndLimit + R"(<dynamics damping="inf" friction="0"/>)"),
       R"(URDF joint 'j': <dynamics damping="inf">)"},
      {R"(<robot name="r"><link name="a"/><link name="b">)" + inertial("1") +
           R"(<visual><origin xyz="nan 0 0"/><geometry><box size="1 1 1"/></geometry></visual></link>)" +
           joint("j", "revolute", kAxisAndLimit) + "</robot>",
       R"(URDF link 'b': <visual><origin xyz="nan 0 0">: 'nan' is not a finite number)"},
      {R"(<robot name="r"><link name="a"/><link name="b">)" + inertial("1") +
           R"(<collision><geometry><cylinder radius="0.1" length="inf"/></geometry></collision></link>)" +
           joint("j", "revolute", kAxisAndLimit) + "</robot>",
       R"(URDF link 'b': <collision><geometry><cylinder length="inf">)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.xml);
    CHECK_THROWS_WITH(model::import_urdf(c.xml), Contains(c.culprit));
  }
}

TEST_CASE("URDF: a number urdfdom cannot read is refused with its message, not read as 0",
          "[urdf][errors]") {
  // urdfdom logs "mass [1,5] is not a float" and keeps the link, massless.
  CHECK_THROWS_WITH(
      model::import_urdf(robot_with(inertial("1,5"), kAxisAndLimit)),
      Contains("URDF") && Contains("mass [1,5] is not a float") && Contains("Link [b]"));
  CHECK_THROWS_WITH(model::import_urdf(robot_with(inertial("1", "0.1x"), kAxisAndLimit)),
                    Contains("URDF") && Contains("Link [b]"));
}

TEST_CASE("URDF: the robot's name is read through the same checks", "[urdf][errors]") {
  CHECK_THROWS_WITH(model::urdf_robot_name(robot_with(inertial("abc"), kAxisAndLimit)),
                    Contains("Link [b]"));
}
