// symdyn-urdf's command line: it generates a URDF robot's code, and its exit
// codes and messages are those of every generator (1: the robot, 2: the command line).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "codegen/run_command.hpp"

using namespace symdyn::testing;
using Catch::Matchers::Contains;

namespace {

const std::string kGenerator = SYMDYN_URDF_GENERATOR;
const std::string kArm = std::string(SYMDYN_URDF_DIR) + "/two_link_arm.urdf";

}  // namespace

TEST_CASE("symdyn-urdf writes <robot>_default.hpp and .cpp, or the --basename", "[urdf][cli]") {
  const auto out = scratch_directory("urdf_cli");
  const CommandResult named = run_command({kGenerator, "--urdf", kArm, "--out", out.string()});
  CHECK(named.exit_code == 0);
  CHECK(std::filesystem::exists(out / "two_link_arm_default.hpp"));
  const CommandResult chosen = run_command({kGenerator, "--urdf", kArm, "--out", out.string(),
                                            "--basename", "arm", "--floating-base", "--stats"});
  CHECK(chosen.exit_code == 0);
  CHECK_THAT(chosen.out, Contains("mass_matrix"));
  // the floating base's coordinates are in the code
  CHECK_THAT(read_text(out / "arm.hpp"), Contains("base_link_yaw"));
  std::filesystem::remove_all(out);
}

TEST_CASE("symdyn-urdf: a missing file exits with 1 naming it, a missing --urdf with 2",
          "[urdf][cli][errors]") {
  const auto out = scratch_directory("urdf_cli");
  const CommandResult missing =
      run_command({kGenerator, "--urdf", "/nonexistent/arm.urdf", "--out", out.string()});
  CHECK(missing.exit_code == 1);
  CHECK_THAT(missing.err, Contains("'/nonexistent/arm.urdf'"));
  CHECK(run_command({kGenerator, "--out", out.string()}).exit_code == 2);
  CHECK(run_command({kGenerator, "--urdf", kArm, "--gravity", "0", "0"}).exit_code == 2);
  std::filesystem::remove_all(out);
}

TEST_CASE(
    "symdyn-urdf: a gravity that is not finite is refused naming --gravity, a NaN in the file "
    "naming the link",
    "[urdf][cli][errors]") {
  const auto out = scratch_directory("urdf_cli");
  const CommandResult gravity = run_command(
      {kGenerator, "--urdf", kArm, "--out", out.string(), "--gravity", "0", "nan", "-9.81"});
  CHECK(gravity.exit_code == 2);
  CHECK_THAT(gravity.err, Contains("--gravity: expected a finite number, found 'nan'"));
  const auto file = out / "bad.urdf";
  std::ofstream(file)
      << R"(<robot name="r"><link name="a"/><link name="b"><inertial><mass value="nan"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>)";
  const CommandResult nan =
      run_command({kGenerator, "--urdf", file.string(), "--out", (out / "gen").string()});
  CHECK(nan.exit_code == 1);
  CHECK_THAT(nan.err,
             Contains(file.string()) && Contains("link 'b'") && Contains("mass value=\"nan\""));
  CHECK_FALSE(std::filesystem::exists(out / "gen"));
  std::filesystem::remove_all(out);
}

TEST_CASE("symdyn-urdf --shapes writes the visuals as a scenario's shapes", "[urdf][cli]") {
  const auto dir = scratch_directory("urdf_cli_shapes");
  std::filesystem::create_directories(dir / "robot" / "urdf");
  std::filesystem::create_directories(dir / "robot" / "meshes");
  std::ofstream(dir / "robot" / "meshes" / "cover.stl") << "solid c\nendsolid c\n";
  std::ofstream(dir / "robot" / "urdf" / "r.urdf") << R"(<robot name="r">
    <link name="a"><inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
      <visual><geometry><box size="0.1 0.2 0.3"/></geometry>
        <material name="blue"><color rgba="0 0 1 1"/></material></visual>
      <visual><geometry><mesh filename="package://robot/meshes/cover.stl"/></geometry></visual>
      <visual><geometry><mesh filename="../meshes/cover.dae"/></geometry></visual>
    </link>
    <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>
    <link name="b"><inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    </robot>)";
  const auto shapes = dir / "out" / "r_shapes.json";
  std::filesystem::create_directories(dir / "out");
  const CommandResult r =
      run_command({kGenerator, "--urdf", (dir / "robot" / "urdf" / "r.urdf").string(), "--out",
                   (dir / "out").string(), "--shapes", shapes.string()});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string json = read_text(shapes);
  CHECK_THAT(json, Contains(R"({"type":"box","size":[0.1,0.2,0.3],"colour":[0.0,0.0,1.0,1.0]})"));
  CHECK_THAT(json, Contains(R"("file":"../robot/meshes/cover.stl")"));
  CHECK_THAT(json, Contains(R"("file":"../robot/meshes/cover.dae")"));
  std::filesystem::remove_all(dir);
}
