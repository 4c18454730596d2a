// A scenario's "shapes" (apps/sim/shapes.hpp): each bad shape is refused at its
// JSON path; good ones reach the scene with the sizes, poses and colours
// written, and a mesh file is read relative to the scenario.
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "codegen/run_command.hpp"
#include "scenario.hpp"
#include "shapes.hpp"

namespace {

using namespace symdyn;
using runtime::Shape;

runtime::Scene scene_of(const std::string& shapes, const std::filesystem::path& dir = {}) {
  const sim::Scenario s = sim::parse_scenario(
      fmt::format(R"j({{"model": "double_pendulum", "shapes": {}}})j", shapes), "test.json", dir);
  return sim::read_scene(s, sim::make_model(s));
}

std::string error_of(const std::string& shapes) {
  try {
    scene_of(shapes);
  } catch (const sim::ScenarioError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("scenario shapes: each bad shape names its culprit by JSON path",
          "[scenario][bad_input]") {
  const std::pair<std::string, std::string> cases[] = {
      {R"j({"rod3": {"type": "sphere", "radius": 1}})j",
       "test.json: /shapes/rod3: unknown body 'rod3' (bodies: rod1, rod2)"},
      {R"j({"rod1": {"type": "cone", "radius": 1}})j",
       "test.json: /shapes/rod1/type: unknown shape type 'cone' (expected: box, sphere, cylinder, "
       "capsule, mesh)"},
      {R"j({"rod1": [{"type": "cylinder", "radius": 0.1}]})j",
       "test.json: /shapes/rod1/0: missing key 'length'"},
      {R"j({"rod1": {"type": "sphere", "radius": -0.1}})j",
       "test.json: /shapes/rod1/radius: expected a number > 0, found -0.1"},
      {R"j({"rod1": {"type": "box", "size": [1, 1]}})j",
       "test.json: /shapes/rod1/size: expected an array of 3 numbers, found 2 entries"},
      {R"j({"rod1": {"type": "box", "size": [1, 0, 1]}})j",
       "test.json: /shapes/rod1/size: a box's edges are > 0, not 0"},
      {R"j({"rod1": {"type": "sphere", "radius": 0.1, "color": "#ff0000"}})j",
       "test.json: /shapes/rod1/color: unknown key 'color' (expected: type, radius, origin, "
       "colour)"},
      {R"j({"rod1": {"type": "sphere", "radius": 0.1, "colour": "red"}})j",
       "test.json: /shapes/rod1/colour: expected a colour \"#rrggbb\" or \"#rrggbbaa\", found "
       "\"red\""},
      {R"j({"rod1": {"type": "sphere", "radius": 0.1, "colour": [1, 0, 2]}})j",
       "test.json: /shapes/rod1/colour/2: a colour's part is in [0, 1], not 2"},
      {R"j({"rod1": {"type": "capsule", "radius": 0.1, "length": 1, "axis": [0, 0, 0]}})j",
       "test.json: /shapes/rod1/axis: an axis needs a length > 0"},
      {R"j({"rod1": {"type": "box", "size": [1, 1, 1], "axes": [[1, 0, 0], [0, 1, 0], [0, 1, 0]]}})j",
       "test.json: /shapes/rod1/axes: the axes must be orthonormal and right-handed (a rotation)"},
      {R"j({"rod1": {"type": "box", "size": [1, 1, 1], "axis": [1, 0, 0], "axes": []}})j",
       "test.json: /shapes/rod1/axes: give \"axis\" or \"axes\", not both"},
      {R"j({"rod1": {"type": "mesh", "file": "no_such_mesh.stl"}})j",
       "test.json: /shapes/rod1/file: mesh 'no_such_mesh.stl'"},
      {R"j({"rod1": 3})j",
       "test.json: /shapes/rod1: expected a shape (an object) or a list of "
       "shapes"},
      {R"j([])j", "test.json: /shapes: expected an object, found an array"},
  };
  for (const auto& [shapes, culprit] : cases) {
    INFO(shapes);
    CHECK_THAT(error_of(shapes), Catch::Matchers::StartsWith(culprit));
  }
}

TEST_CASE("scenario shapes: sizes, poses and colours reach the scene", "[scenario]") {
  const runtime::Scene scene = scene_of(R"j({
    "rod1": [
      {"type": "cylinder", "radius": 0.05, "length": 1, "axis": [1, 0, 0], "colour": "#ff8000"},
      {"type": "sphere", "radius": 0.1, "origin": [0.5, 0, 0], "colour": [0, 0.5, 1, 0.25]}
    ],
    "rod2": []
  })j");
  REQUIRE(scene.shapes(0).size() == 2);
  const Shape& rod = scene.shapes(0)[0];
  CHECK(rod.kind == Shape::Kind::cylinder);
  CHECK(rod.size.head<2>() == runtime::Vec3(0.05, 1, 0).head<2>());
  // The cylinder's axis, its local z, along the body's x.
  CHECK((rod.pose.linear() * runtime::Vec3::UnitZ() - runtime::Vec3::UnitX()).norm() < 1e-12);
  CHECK(rod.colour.r == 1.0f);
  CHECK(rod.colour.g == Approx(128 / 255.0));
  CHECK(rod.colour.b == 0.0f);
  const Shape& ball = scene.shapes(0)[1];
  CHECK(ball.kind == Shape::Kind::sphere);
  CHECK((ball.pose.translation() - runtime::Vec3(0.5, 0, 0)).norm() == 0);
  CHECK(ball.colour.a == 0.25f);
  CHECK(scene.shapes(1).empty());  // hidden

  // A body not named keeps its default shapes (a rod from the elbow to its G,
  // its inertia's cylinder) and its own colour.
  const runtime::Scene plain = scene_of(R"j({"rod1": {"type": "sphere", "radius": 0.1}})j");
  REQUIRE(plain.shapes(1).size() == 2);
  CHECK(plain.shapes(1)[0].kind == Shape::Kind::capsule);
  CHECK(plain.shapes(1)[1].kind == Shape::Kind::cylinder);
  const runtime::Colour c = runtime::body_colour(1);
  for (const Shape& shape : plain.shapes(1)) {
    const runtime::Colour own = shape.colour;
    CHECK((own.r == c.r && own.g == c.g && own.b == c.b));
  }
  CHECK(plain.shapes(0)[0].colour.r == runtime::body_colour(0).r);  // colour omitted: the body's
}

TEST_CASE("scenario shapes: a mesh file is read relative to the scenario, scaled", "[scenario]") {
  const auto dir = testing::scratch_directory("scenario_shapes");
  std::filesystem::create_directories(dir / "meshes");
  // A tetrahedron in millimetres.
  std::ofstream(dir / "meshes" / "tetra.obj")
      << "v 0 0 0\nv 1000 0 0\nv 0 1000 0\nv 0 0 1000\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const runtime::Scene scene =
      scene_of(R"j({"rod2": {"type": "mesh", "file": "meshes/tetra.obj", "scale": 0.001}})j", dir);
  REQUIRE(scene.shapes(1).size() == 1);
  const Shape& mesh = scene.shapes(1)[0];
  REQUIRE(mesh.kind == Shape::Kind::mesh);
  CHECK(mesh.mesh->triangle_count() == 4);
  float largest = 0;
  for (const auto& p : mesh.mesh->positions) largest = std::max(largest, p.maxCoeff());
  CHECK(largest == Approx(1.0));
  std::filesystem::remove_all(dir);
}

TEST_CASE("scenario shapes: a file of shapes, its meshes relative to it, scaled per axis",
          "[scenario]") {
  const auto dir = testing::scratch_directory("scenario_shapes_file");
  std::filesystem::create_directories(dir / "robot" / "meshes");
  // A unit right tetrahedron, scaled by (2, 3, 4): its normals turn as n / s.
  std::ofstream(dir / "robot" / "meshes" / "tetra.obj")
      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  std::ofstream(dir / "robot" / "shapes.json") << R"j({
    "rod2": [{"type": "mesh", "file": "meshes/tetra.obj", "scale": [2, 3, 4]}]
  })j";
  const runtime::Scene scene = scene_of(R"j("robot/shapes.json")j", dir);
  REQUIRE(scene.shapes(1).size() == 1);
  const runtime::TriangleMesh& m = *scene.shapes(1)[0].mesh;
  Eigen::Vector3f largest = Eigen::Vector3f::Zero();
  for (const auto& p : m.positions) largest = largest.cwiseMax(p);
  CHECK((largest - Eigen::Vector3f(2, 3, 4)).norm() < 1e-6f);
  // The slanted face x/2 + y/3 + z/4 = 1: its normal along (1/2, 1/3, 1/4).
  const Eigen::Vector3f slanted = Eigen::Vector3f(1 / 2.0f, 1 / 3.0f, 1 / 4.0f).normalized();
  bool found = false;
  for (const auto& n : m.normals) found = found || (n - slanted).norm() < 1e-5f;
  CHECK(found);

  std::ofstream(dir / "robot" / "bad.json") << R"j({"rod3": []})j";
  const auto error = [&](const std::string& shapes) {
    try {
      scene_of(shapes, dir);
    } catch (const sim::ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK_THAT(error(R"j("robot/bad.json")j"),
             Catch::Matchers::Contains("robot/bad.json: /rod3: unknown body 'rod3'"));
  CHECK_THAT(error(R"j("robot/none.json")j"),
             Catch::Matchers::StartsWith("test.json: /shapes: cannot read the shapes file") &&
                 Catch::Matchers::Contains("none.json"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("scenario shapes: a COLLADA mesh through Assimp, in its unit", "[scenario]") {
  const auto dir = testing::scratch_directory("scenario_shapes_dae");
  // A right tetrahedron of edges 100 cm, Z up.
  std::ofstream(dir / "tetra.dae") << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tetra" name="tetra">
      <mesh>
        <source id="tetra-positions">
          <float_array id="tetra-positions-array" count="12">0 0 0 100 0 0 0 100 0 0 0 100</float_array>
          <technique_common><accessor source="#tetra-positions-array" count="4" stride="3">
            <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
          </accessor></technique_common>
        </source>
        <vertices id="tetra-vertices"><input semantic="POSITION" source="#tetra-positions"/></vertices>
        <triangles count="4"><input semantic="VERTEX" source="#tetra-vertices" offset="0"/>
          <p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="tetra-node"><instance_geometry url="#tetra"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
  const std::string shapes = R"j({"rod1": {"type": "mesh", "file": "tetra.dae"}})j";
#ifdef SYMDYN_HAVE_ASSIMP
  const runtime::Scene scene = scene_of(shapes, dir);
  const runtime::TriangleMesh& m = *scene.shapes(0)[0].mesh;
  CHECK(m.triangle_count() == 4);
  Eigen::Vector3f largest = Eigen::Vector3f::Zero();
  for (const auto& p : m.positions) largest = largest.cwiseMax(p);
  CHECK((largest - Eigen::Vector3f(1, 1, 1)).norm() < 1e-6f);  // metres, axes as written
#else
  CHECK_THROWS_WITH(scene_of(shapes, dir), Catch::Matchers::Contains("tetra.dae") &&
                                               Catch::Matchers::Contains("built without Assimp"));
#endif
  std::filesystem::remove_all(dir);
}
