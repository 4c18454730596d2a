// Shapes, the animation writers and the mesh readers, each checked by another
// route: volumes and inertias of the tessellated shapes by the divergence
// theorem, glTF files read back by an independent reader (tinygltf), poses
// against the double pendulum's closed-form kinematics.
#include <fmt/format.h>
#include <tiny_gltf.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/rigid_body.hpp"
#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/easyanim.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/gltf.hpp>
#include <symdyn/runtime/html_viewer.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/scene.hpp>

using namespace symdyn::runtime;
using Catch::Matchers::Contains;

namespace {

// Volume, centroid and inertia about the centroid of a closed mesh of uniform
// density 1, summed over the tetrahedra (origin, a, b, c) of its triangles:
// covariance (det/120)·(Σ v vᵀ + s sᵀ), s = a + b + c, det = a·(b×c).
struct MassProperties {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

MassProperties mass_properties(const TriangleMesh& m) {
  MassProperties p;
  Mat3 covariance = Mat3::Zero();
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 a = m.positions[m.indices[3 * t]].cast<double>();
    const Vec3 b = m.positions[m.indices[3 * t + 1]].cast<double>();
    const Vec3 c = m.positions[m.indices[3 * t + 2]].cast<double>();
    const double det = a.dot(b.cross(c));
    const Vec3 s = a + b + c;
    p.volume += det / 6;
    p.centroid += det / 24 * s;
    covariance +=
        det / 120 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  p.centroid /= p.volume;
  covariance -= p.volume * p.centroid * p.centroid.transpose();  // about the centroid
  p.inertia = covariance.trace() * Mat3::Identity() - covariance;
  return p;
}

// Every vertex normal on the outer side of its triangle.
bool normals_point_out(const TriangleMesh& m) {
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const auto& a = m.positions[m.indices[3 * t]];
    const Eigen::Vector3f face =
        (m.positions[m.indices[3 * t + 1]] - a).cross(m.positions[m.indices[3 * t + 2]] - a);
    for (int k = 0; k < 3; ++k) {
      if (face.dot(m.normals[m.indices[3 * t + k]]) <= 0) return false;
    }
  }
  return true;
}

std::filesystem::path temp_file(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "symdyn_scene_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

// The double pendulum's poses in closed form: rod1 at angle q0, rod2 at q0 + q1.
Vec3 rod2_centre(double q0, double q1) {
  return Vec3(std::cos(q0) + 0.5 * std::cos(q0 + q1), std::sin(q0) + 0.5 * std::sin(q0 + q1), 0);
}

State pendulum_state(double t) {
  State s;
  s.t = t;
  s.q = Vector::Zero(2);
  s.q << 0.3 + 2.0 * t, -1.1 + 5.0 * t;  // several turns over the frames
  s.qd = Vector::Zero(2);
  return s;
}

// The floats of a glTF accessor, read through its buffer view.
std::vector<float> floats(const tinygltf::Model& g, int accessor) {
  const auto& a = g.accessors[accessor];
  const auto& v = g.bufferViews[a.bufferView];
  const int n = tinygltf::GetNumComponentsInType(a.type);
  std::vector<float> out(a.count * n);
  std::memcpy(out.data(), g.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset,
              out.size() * 4);
  return out;
}

}  // namespace

TEST_CASE("Tessellated shapes are closed, face outwards and converge to their volumes",
          "[runtime][scene]") {
  const double r = 0.2, L = 0.7, pi = std::numbers::pi;
  CHECK(mass_properties(tessellate(Shape::box(0.3, 0.5, 0.7))).volume ==
        Approx(0.105).epsilon(1e-6));
  struct Case {
    Shape shape;
    double volume;
  };
  for (const auto& [shape, volume] :
       {Case{Shape::sphere(r), 4 * pi * r * r * r / 3}, Case{Shape::cylinder(r, L), pi * r * r * L},
        Case{Shape::capsule(r, L), pi * r * r * L + 4 * pi * r * r * r / 3}}) {
    double previous_error = 1.0;
    for (const int segments : {8, 32, 128}) {
      const TriangleMesh m = tessellate(shape, segments);
      CHECK(normals_point_out(m));
      const double error = std::abs(mass_properties(m).volume / volume - 1);
      CHECK(error < previous_error);  // an inscribed polyhedron, refined
      previous_error = error;
    }
    CHECK(previous_error < 2e-3);
  }
}

TEST_CASE("A shape's pose moves its mesh and its centroid", "[runtime][scene]") {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Vec3(1, -2, 0.5)).rotate(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const MassProperties p = mass_properties(tessellate(Shape::box(0.1, 0.2, 0.3).at(pose)));
  CHECK((p.centroid - Vec3(1, -2, 0.5)).norm() < 1e-6);
  CHECK(p.volume == Approx(0.006).epsilon(1e-5));
}

TEST_CASE("The inertia box has the body's mass, inertia and principal axes", "[runtime][scene]") {
  // A full, positive definite tensor with distinct moments, turned off the body axes.
  const Mat3 turn = Eigen::AngleAxisd(0.9, Vec3(0.3, -1, 2).normalized()).toRotationMatrix();
  const Mat3 I = turn * Vec3(0.04, 0.05, 0.07).asDiagonal() * turn.transpose();
  const double mass = 3.0;
  const MassProperties p = mass_properties(tessellate(inertia_box(mass, I)));
  const Mat3 box_inertia = mass / p.volume * p.inertia;  // density mass / volume
  CHECK((box_inertia - I).norm() / I.norm() < 1e-5);
  CHECK(p.centroid.norm() < 1e-6);
}

TEST_CASE("A slender body's inertia box keeps a visible thickness", "[runtime][scene]") {
  // A thin rod along x: its moment about x vanishes, so would two edges.
  const Shape box = inertia_box(1.0, Vec3(0.0, 1.0 / 12, 1.0 / 12).asDiagonal());
  const Vec3 edges = box.size;
  CHECK(edges.maxCoeff() == Approx(1.0).epsilon(1e-12));
  CHECK(edges.minCoeff() == Approx(0.02).epsilon(1e-12));
}

TEST_CASE("The inertia cylinder of a wheel or a rod has the body's mass and inertia",
          "[runtime][scene]") {
  // A solid disc about y (r = 0.3, l = 0.12: A = m r²/2, B = m (3 r² + l²)/12) and a rod
  // about a skew axis (r = 0.02, l = 1), each a uniform cylinder: read back by the
  // divergence theorem from 256 facets around.
  const Mat3 turn = Eigen::AngleAxisd(0.6, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const double m = 5.0;
  const auto moments = [&](double r, double l) {
    return Vec3(m * (3 * r * r + l * l) / 12, m * (3 * r * r + l * l) / 12, m * r * r / 2);
  };
  const Vec3 disc = moments(0.3, 0.12), rod = moments(0.02, 1.0);
  for (const Mat3& I : {Mat3(Vec3(disc.x(), disc.z(), disc.y()).asDiagonal()),
                        Mat3(turn * rod.asDiagonal() * turn.transpose())}) {
    const auto cylinder = inertia_cylinder(m, I);
    REQUIRE(cylinder);
    CHECK(cylinder->kind == Shape::Kind::cylinder);
    const MassProperties p = mass_properties(tessellate(*cylinder, 256));
    CHECK((m / p.volume * p.inertia - I).norm() / I.norm() < 1e-3);
    CHECK(p.centroid.norm() < 1e-6);
  }
  // Three distinct moments: no cylinder, the box.
  CHECK_FALSE(inertia_cylinder(m, Vec3(0.04, 0.05, 0.07).asDiagonal()));
  CHECK(inertia_shape(m, Vec3(0.04, 0.05, 0.07).asDiagonal()).kind == Shape::Kind::box);
}

TEST_CASE("A thin wheel keeps a visible width; equal or no moments make a ball",
          "[runtime][scene]") {
  // The trike's wheels: m = 5, moments (0.2, 0.4, 0.2), a disc of no width (r = 0.4).
  const auto wheel = inertia_cylinder(5.0, Vec3(0.2, 0.4, 0.2).asDiagonal());
  REQUIRE(wheel);
  CHECK(wheel->size.x() == Approx(0.4));
  CHECK(wheel->size.y() == Approx(0.1));  // a quarter of the radius
  CHECK(std::abs((wheel->pose.linear() * Vec3::UnitZ()).y()) == Approx(1.0));  // about y
  // A uniform ball: I = 2/5 m r².
  const Shape ball = inertia_shape(2.0, Mat3::Identity() * 0.4 * 2.0 * 0.25 * 0.25);
  CHECK(ball.kind == Shape::Kind::sphere);
  CHECK(ball.size.x() == Approx(0.25));
  // A point mass: a ball of water, 4/3 pi r³ 1000 = m.
  const Shape drop = inertia_shape(0.5, Mat3::Zero());
  CHECK(drop.kind == Shape::Kind::sphere);
  CHECK(4.0 / 3.0 * std::numbers::pi * std::pow(drop.size.x(), 3) * 1000.0 == Approx(0.5));
}

TEST_CASE("Each body's default shape has a colour apart from its neighbours'", "[runtime][scene]") {
  const Model model = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  const Scene scene(model);
  const Colour a = scene.shapes(0)[0].colour, b = scene.shapes(1)[0].colour;
  CHECK(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) > 0.3f);
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < i; ++j) {
      const Colour ci = body_colour(i), cj = body_colour(j);
      CHECK(std::abs(ci.r - cj.r) + std::abs(ci.g - cj.g) + std::abs(ci.b - cj.b) > 0.15f);
    }
  }
}

TEST_CASE("The viewer's units: rad for a coordinate that turns a body, m else",
          "[runtime][scene]") {
  // The free block: x, y, z translate it, yaw, pitch, roll turn it (its fixture).
  const Model block = Model::from<symdyn_fixtures::rigid_body>();
  CHECK(coordinate_units(block) == std::vector<std::string>{"m", "m", "m", "rad", "rad", "rad"});
  const Model pendulum = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  CHECK(coordinate_units(pendulum) == std::vector<std::string>{"rad", "rad"});
  if (!html_viewer_available()) return;
  const TimeSeries series{{"t", "q0"}, {{0.0}, {1.0}}, {"s"}};
  CHECK_THROWS_WITH(write_html(temp_file("units.html"), "units", Scene(pendulum), {}, series),
                    Contains("1 series units for 2 names"));
}

TEST_CASE("The viewer's arrows: 3 values of point and vector per time, else refused",
          "[runtime][scene]") {
  // (Drawn: tests/viewer/check_four_bar_viewer.py.)
  if (!html_viewer_available()) return;
  const Model pendulum = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  const TimeSeries series{{"t", "q0"}, {{0.0, 0.1}, {1.0, 1.1}}, {"s", "rad"}};
  const auto html = [&](const Arrows& arrows) {
    write_html(temp_file("arrows.html"), "arrows", Scene(pendulum), {}, series, arrows);
  };
  CHECK_THROWS_WITH(html({{"C"}, {{0, 0, 0, 1, 0, 0}}, {}}),
                    Contains("1 arrow names for 1 points and 0 vectors"));
  CHECK_THROWS_WITH(html({{"C"}, {{0, 0, 0}}, {{1, 2, 0, 1, 2, 0}}}),
                    Contains("arrow 'C' has 3 point and 6 vector values, 3 per time (6)"));
}

TEST_CASE("Bad shapes are refused naming the dimension", "[runtime][scene]") {
  CHECK_THROWS_WITH(Shape::sphere(-1), Contains("sphere radius") && Contains("-1"));
  CHECK_THROWS_WITH(Shape::box(1, std::nan(""), 1), Contains("box edge y"));
  CHECK_THROWS_WITH(Shape::cylinder(0.1, 0), Contains("cylinder length"));
  CHECK_THROWS_AS(Shape::triangles(nullptr), ModelError);
}

TEST_CASE("OBJ and STL files are read as closed meshes", "[runtime][scene]") {
  // A unit cube in OBJ, quads, one face with negative (relative) indices and texture references.
  const auto obj = temp_file("cube.obj");
  write_text(obj,
             "# cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2/1 3/1 7/1 6/1\nf 3 4 8 7\nf -4 -8 -5 -1\n");
  const TriangleMesh cube = read_mesh(obj);
  CHECK(cube.triangle_count() == 12);
  CHECK(mass_properties(cube).volume == Approx(1.0).epsilon(1e-6));

  // The tetrahedron (0, e1, e2, e3), binary and ASCII STL.
  const Eigen::Vector3f v[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string binary(80, ' ');
  std::string ascii = "solid tetra\n";
  const std::uint32_t count = 4;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : faces) {
    const float zero[3] = {0, 0, 0};
    binary.append(reinterpret_cast<const char*>(zero), 12);
    ascii += "facet normal 0 0 0\nouter loop\n";
    for (const int k : f) {
      binary.append(reinterpret_cast<const char*>(v[k].data()), 12);
      ascii += fmt::format("vertex {} {} {}\n", v[k].x(), v[k].y(), v[k].z());
    }
    binary.append(2, '\0');
    ascii += "endloop\nendfacet\n";
  }
  write_text(temp_file("tetra.stl"), binary);
  write_text(temp_file("tetra_ascii.STL"), ascii + "endsolid tetra\n");
  for (const char* name : {"tetra.stl", "tetra_ascii.STL"}) {
    const TriangleMesh m = read_mesh(temp_file(name));
    CHECK(m.triangle_count() == 4);
    CHECK(mass_properties(m).volume == Approx(1.0 / 6).epsilon(1e-6));
    CHECK(normals_point_out(m));
  }
}

TEST_CASE("Bad mesh files are refused naming the file and the line", "[runtime][scene]") {
  const auto obj = temp_file("bad.obj");
  write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  CHECK_THROWS_WITH(read_mesh(obj), Contains("bad.obj") && Contains("line 4") &&
                                        Contains("vertex 4 does not exist"));
  write_text(obj, "v 0 0 nan\n");
  CHECK_THROWS_WITH(read_mesh(obj), Contains("line 1"));
  write_text(obj, "v 0 0 0\n");
  CHECK_THROWS_WITH(read_mesh(obj), Contains("has no triangle"));
  const auto stl = temp_file("short.stl");
  write_text(stl, std::string(90, 'x'));
  CHECK_THROWS_WITH(read_mesh(stl), Contains("short.stl") && Contains("bytes"));
  CHECK_THROWS_WITH(read_mesh(temp_file("mesh.ply")), Contains("mesh.ply"));
}

TEST_CASE("glTF: nodes, times and poses read back by tinygltf match the kinematics",
          "[runtime][scene]") {
  const Model model = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  Scene scene(model);
  scene.add(1, Shape::cylinder(0.02, 1.0).with({0.8f, 0.2f, 0.1f, 1.0f}));
  scene.add(1, Shape::sphere(0.05));
  Animation animation(model);
  const std::vector<double> times = {0.5, 0.6, 0.75, 1.0};
  for (const double t : times) animation.record(pendulum_state(t));
  const auto file = temp_file("pendulum.glb");
  write_glb(file, scene, animation);

  tinygltf::Model g;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  REQUIRE(loader.LoadBinaryFromFile(&g, &error, &warning, file.string()));
  CHECK(error.empty());
  CHECK(warning.empty());
  REQUIRE(g.nodes.size() == 3);  // world, rod1, rod2
  CHECK(g.nodes[0].name == "world");
  CHECK(g.nodes[0].children == std::vector<int>{1, 2});
  CHECK(g.nodes[1].name == "rod1");
  CHECK(g.nodes[2].name == "rod2");
  CHECK(g.meshes[g.nodes[2].mesh].primitives.size() == 2);  // the two shapes added
  // Gravity along -y: up is already glTF's +Y.
  CHECK(Eigen::Quaterniond(g.nodes[0].rotation[3], g.nodes[0].rotation[0], g.nodes[0].rotation[1],
                           g.nodes[0].rotation[2])
            .angularDistance(Eigen::Quaterniond::Identity()) < 1e-12);

  REQUIRE(g.animations.size() == 1);
  for (const auto& channel : g.animations[0].channels) {
    const auto& sampler = g.animations[0].samplers[channel.sampler];
    const std::vector<float> input = floats(g, sampler.input);
    const std::vector<float> output = floats(g, sampler.output);
    REQUIRE(input.size() == times.size());
    for (std::size_t k = 0; k < times.size(); ++k) {
      CHECK(input[k] == Approx(times[k] - times[0]).margin(1e-6));
      if (channel.target_node != 2) continue;
      const State s = pendulum_state(times[k]);
      if (channel.target_path == "translation") {
        const Vec3 x(output[3 * k], output[3 * k + 1], output[3 * k + 2]);
        CHECK((x - rod2_centre(s.q[0], s.q[1])).norm() < 1e-6);
      } else {
        const Eigen::Quaterniond q(output[4 * k + 3], output[4 * k], output[4 * k + 1],
                                   output[4 * k + 2]);
        const Eigen::Quaterniond expected(Eigen::AngleAxisd(s.q[0] + s.q[1], Vec3::UnitZ()));
        CHECK(q.angularDistance(expected) < 1e-6);
        if (k > 0) {  // the short way between frames
          const Eigen::Vector4f a(&output[4 * k]), b(&output[4 * (k - 1)]);
          CHECK(a.dot(b) >= 0);
        }
      }
    }
  }
}

TEST_CASE("glTF of a z-up model turns z onto glTF's +Y", "[runtime][scene]") {
  using Pendulum = symdyn_fixtures::double_pendulum_absolute;
  ModelDescription d;  // the pendulum's kinematics under gravity along -z
  d.model = "z_up";
  d.nq = d.nbody = 2;
  d.q_names = {"q0", "q1"};
  d.body_names = {"rod1", "rod2"};
  d.q_initial = d.qd_initial = {0.0, 0.0};
  d.reference_body = {-1, -1};
  d.gravity = Vec3(0, 0, -9.81);
  d.inertia = &Pendulum::inertia;
  d.positions = &Pendulum::positions;
  const Model model(d);
  Scene scene(model);
  Animation animation(model);
  animation.record(pendulum_state(0));
  std::ostringstream out;
  write_glb(out, scene, animation);
  tinygltf::Model g;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  const std::string bytes = out.str();
  REQUIRE(loader.LoadBinaryFromMemory(&g, &error, &warning,
                                      reinterpret_cast<const unsigned char*>(bytes.data()),
                                      static_cast<unsigned>(bytes.size())));
  const auto& r = g.nodes[0].rotation;
  const Eigen::Quaterniond world(r[3], r[0], r[1], r[2]);
  CHECK((world * Vec3::UnitZ() - Vec3::UnitY()).norm() < 1e-12);
  CHECK(g.animations.empty());  // one frame: a still scene
}

TEST_CASE("Animation refuses frames out of order", "[runtime][scene]") {
  const Model model = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  Animation animation(model);
  animation.record(pendulum_state(1.0));
  CHECK_THROWS_WITH(animation.record(pendulum_state(0.5)),
                    Contains("t = 0.5") && Contains("increase"));
  std::ostringstream out;
  CHECK_THROWS_AS(write_glb(out, Scene(model), Animation(model)), OptionError);
}

TEST_CASE("EasyAnim: every node of .van follows its body", "[runtime][scene]") {
  const Model model = Model::from<symdyn_fixtures::double_pendulum_absolute>();
  Scene scene(model);
  for (int body = 0; body < 2; ++body) scene.add(body, Shape::box(1.0, 0.1, 0.1));
  Animation animation(model);
  const std::vector<double> times = {0.0, 0.3, 0.9};
  for (const double t : times) animation.record(pendulum_state(t));
  const auto stem = temp_file("pendulum");
  write_easyanim(stem, scene, animation, "double pendulum");

  std::ifstream vol(stem.string() + ".vol");
  std::string title;
  std::getline(vol, title);
  CHECK(title == "double pendulum");
  std::size_t nodes = 0;
  vol >> nodes;
  REQUIRE(nodes == 16);  // two boxes of 8 corners
  std::vector<Vec3> first(nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    std::size_t name = 0;
    vol >> name >> first[i].x() >> first[i].y() >> first[i].z();
    CHECK(name == i);
  }
  std::size_t edges = 1, faces = 0;
  vol >> edges >> faces;
  CHECK(edges == 0);
  CHECK(faces == 24);

  std::ifstream van(stem.string() + ".van");
  for (std::size_t k = 0; k < times.size(); ++k) {
    const State s = pendulum_state(times[k]), s0 = pendulum_state(times[0]);
    for (std::size_t i = 0; i < nodes; ++i) {
      Vec3 p;
      van >> p.x() >> p.y() >> p.z();
      // Node i of rod2 (the last 8): its offset from G turns with q0 + q1.
      if (i < 8) continue;
      const Eigen::AngleAxisd turn(s.q[0] + s.q[1] - s0.q[0] - s0.q[1], Vec3::UnitZ());
      const Vec3 expected =
          rod2_centre(s.q[0], s.q[1]) + turn * (first[i] - rod2_centre(s0.q[0], s0.q[1]));
      CHECK((p - expected).norm() < 1e-6);
    }
  }
  double extra;
  CHECK_FALSE(van >> extra);
}

TEST_CASE("EasyAnim modes: the pole, then the scene displaced by each part of the shape",
          "[runtime][scene]") {
  MultibodySystem system(Model::from<symdyn_fixtures::double_pendulum_absolute>());
  State hanging = system.initial_state();
  hanging.q << -std::numbers::pi / 2, 0;
  const Linearization lin = linearize(system, hanging);
  const std::vector<Mode> m = modes(lin);
  const auto stem = temp_file("pendulum_modes");
  Scene boxes(system.model());  // 8 nodes a body
  for (int body = 0; body < 2; ++body) boxes.add(body, Shape::box(1.0, 0.1, 0.1));
  write_easyanim_modes(stem, boxes, system.model(), hanging, lin, m, 0.1, "modes");
  std::ifstream vmo(stem.string() + ".vmo");
  std::vector<double> numbers;
  for (double v; vmo >> v;) numbers.push_back(v);
  const std::size_t nodes = 16;
  REQUIRE(numbers.size() == m.size() * (4 + 2 * 3 * nodes));
  CHECK(numbers[0] == Approx(m[0].pole.real()).margin(1e-12));
  CHECK(numbers[1] == Approx(m[0].pole.imag()));
  CHECK(numbers[2] == Approx(m[0].natural_frequency_hz));
}

TEST_CASE("A mode's animation swings about the reference by its shape over one period",
          "[runtime][scene]") {
  MultibodySystem system(Model::from<symdyn_fixtures::double_pendulum_absolute>());
  State hanging = system.initial_state();
  hanging.q << -std::numbers::pi / 2, 0;
  const Linearization lin = linearize(system, hanging);
  const Mode mode = modes(lin).front();
  const Animation a = mode_animation(system, hanging, lin, mode, 0.1, 8);
  REQUIRE(a.frames() == 9);
  CHECK(a.time(8) - a.time(0) == Approx(2 * std::numbers::pi / mode.pole.imag()));
  // Frame 2 is a quarter period: q = q_ref + a·Re(psi·i), psi scaled to 0.1 at its largest.
  const Eigen::VectorXcd psi = mode.shape / mode.shape.cwiseAbs().maxCoeff() * 0.1;
  for (const auto& [frame, phase] :
       {std::pair{0, std::complex<double>(1, 0)}, std::pair{2, std::complex<double>(0, 1)}}) {
    const double q0 = hanging.q[0] + (psi[0] * phase).real(),
                 q1 = hanging.q[1] + (psi[1] * phase).real();
    CHECK((a.translation(frame, 1) - rod2_centre(q0, q1)).norm() < 1e-12);
    CHECK(a.rotation(frame, 1).angularDistance(
              Eigen::Quaterniond(Eigen::AngleAxisd(q0 + q1, Vec3::UnitZ()))) < 1e-12);
  }
  CHECK((a.translation(8, 1) - a.translation(0, 1)).norm() < 1e-12);  // one whole period
}
