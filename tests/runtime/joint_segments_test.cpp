// The default stick figures (scene.hpp, joint_segments) from the emitted joint
// points, against the joints placed by direct products of the models'
// homogeneous transformation matrices at random states; and
// their rods in the scene and in the glTF file read back by tinygltf.
#include <tiny_gltf.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <random>

#include "double_pendulum_absolute.hpp"
#include "double_pendulum_relative.hpp"
#include "robot3d_absolute.hpp"
#include "robot3d_relative.hpp"
#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/gltf.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/scene.hpp>

using namespace symdyn::runtime;

namespace {

using Frame = Eigen::Matrix4d;

Frame rotation(const Vec3& axis, double angle) {
  Frame T = Frame::Identity();
  T.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return T;
}
Frame Trotx(double a) {
  return rotation(Vec3::UnitX(), a);
}
Frame Troty(double a) {
  return rotation(Vec3::UnitY(), a);
}
Frame Trotz(double a) {
  return rotation(Vec3::UnitZ(), a);
}
Frame Tdisp(double x, double y, double z) {
  Frame T = Frame::Identity();
  T.topRightCorner<3, 1>() = Vec3(x, y, z);
  return T;
}
Vec3 origin(const Frame& T) {
  return T.topRightCorner<3, 1>();
}

using Points = std::vector<std::pair<Vec3, Vec3>>;  // segments, global frame

// Every body's segments at q placed by the emitted positions, in body order.
Points placed_segments(const Model& model, const Vector& q) {
  Kinematics k = model.make_kinematics();
  model.positions(0.0, q.data(), k);
  Points out;
  const auto segments = joint_segments(model);
  for (int i = 0; i < model.nbody(); ++i) {
    for (const Segment& s : segments[i])
      out.emplace_back(k.x(i) + k.R(i) * s.from, k.x(i) + k.R(i) * s.to);
  }
  return out;
}

void check_same(const Points& found, const Points& expected) {
  REQUIRE(found.size() == expected.size());
  for (std::size_t k = 0; k < found.size(); ++k) {
    INFO("segment " << k);
    CHECK((found[k].first - expected[k].first).norm() < 1e-12);
    CHECK((found[k].second - expected[k].second).norm() < 1e-12);
  }
}

Vector random_q(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  Vector q(n);
  for (int j = 0; j < n; ++j) q[j] = angle(rng);
  return q;
}

}  // namespace

TEST_CASE("Stick figures: the double pendulum's rods from the pivot to the elbow to rod2's G",
          "[runtime][scene]") {
  const Model relative = Model::from<symdyn_generated::double_pendulum_relative>();
  const Model absolute = Model::from<symdyn_generated::double_pendulum_absolute>();
  std::mt19937 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    const Vector q = random_q(rng, 2);
    const Frame elbow = Trotz(q[0]) * Tdisp(1.0, 0, 0);
    const Vec3 pivot = Vec3::Zero(), G1 = origin(Trotz(q[0]) * Tdisp(0.5, 0, 0)),
               G2 = origin(elbow * Trotz(q[1]) * Tdisp(0.5, 0, 0));
    // rod2 hangs on rod1: rod1 reaches the elbow; described from the ground, rod1 has no child.
    check_same(placed_segments(relative, q), {{pivot, origin(elbow)}, {origin(elbow), G2}});
    check_same(placed_segments(absolute, q), {{pivot, G1}, {origin(elbow), G2}});
  }
}

TEST_CASE("Stick figures: robot3d's turret to the shoulder, arm to the wrist, wrist to G",
          "[runtime][scene]") {
  const Model relative = Model::from<symdyn_generated::robot3d_relative>();
  const Model absolute = Model::from<symdyn_generated::robot3d_absolute>();
  const double H = 0.5, L = 1.0, C = 0.2;  // models/robot3d.cpp
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> length(0.2, 1.5);
  for (int trial = 0; trial < 10; ++trial) {
    Vector q = random_q(rng, 5);
    q[2] = length(rng);  // the arm's extension
    const Frame shoulder = Trotz(q[0]) * Tdisp(0, 0, H) * Troty(q[1]);
    const Frame arm = shoulder * Tdisp(q[2], 0, 0), wrist = arm * Tdisp(L / 2, 0, 0);
    const Vec3 G_turret = origin(Trotz(q[0]) * Tdisp(0, 0, H / 2)),
               G_gripper = origin(wrist * Trotx(q[3]) * Troty(q[4]) * Tdisp(C, 0, 0));
    // Relative: turret pivot to shoulder; the arm's joint (the slider's end) is its G.
    check_same(placed_segments(relative, q), {{Vec3::Zero(), origin(shoulder)},
                                              {origin(arm), origin(wrist)},
                                              {origin(wrist), G_gripper}});
    // Absolute: no child; the arm's G at its joint leaves it no segment.
    check_same(placed_segments(absolute, q),
               {{Vec3::Zero(), G_turret}, {origin(wrist), G_gripper}});
  }
}

TEST_CASE("Default shapes: a rod along each segment, the inertia's solid unless a box",
          "[runtime][scene]") {
  const Vec3 a(0.1, 0.2, -0.3), b(-0.4, 0.5, 0.6);
  const Mat3 box = Vec3(1.0, 2.0, 2.5).asDiagonal(), wheel = Vec3(2.0, 1.0, 1.0).asDiagonal();
  const std::vector<Shape> rods = default_shapes(3.0, box, {{a, b}}, 0.02);
  REQUIRE(rods.size() == 1);
  CHECK(rods[0].kind == Shape::Kind::capsule);
  CHECK(rods[0].size.x() == 0.02);
  CHECK(rods[0].size.y() == Approx((b - a).norm()));
  // The capsule's end caps are centred on the segment's ends.
  CHECK((rods[0].pose * Vec3(0, 0, -rods[0].size.y() / 2) - a).norm() < 1e-12);
  CHECK((rods[0].pose * Vec3(0, 0, rods[0].size.y() / 2) - b).norm() < 1e-12);
  // A short segment's rod is at most a tenth as thick as it is long.
  CHECK(default_shapes(3.0, box, {{a, a + Vec3(0.05, 0, 0)}}, 0.02)[0].size.x() == Approx(0.005));
  const std::vector<Shape> wheel_shapes = default_shapes(3.0, wheel, {{a, b}}, 0.02);
  REQUIRE(wheel_shapes.size() == 2);
  CHECK(wheel_shapes[1].kind == Shape::Kind::cylinder);
  const std::vector<Shape> alone = default_shapes(3.0, box, {}, 0.02);
  REQUIRE(alone.size() == 1);
  CHECK(alone[0].kind == Shape::Kind::box);
}

TEST_CASE("Default shapes: the scene and its glTF file hold the rods", "[runtime][scene]") {
  const Model model = Model::from<symdyn_generated::double_pendulum_relative>();
  const Scene scene(model);
  // rod1: its rod to the elbow (from G: -l1/2 to +l1/2 along x) and its inertia's cylinder.
  REQUIRE(scene.shapes(0).size() == 2);
  const Shape& rod = scene.shapes(0)[0];
  CHECK(rod.kind == Shape::Kind::capsule);
  CHECK(rod.size.x() == Approx(0.02));  // 2 % of the longest segment, rod1's 1 m
  CHECK((rod.pose * Vec3(0, 0, -0.5) - Vec3(-0.5, 0, 0)).norm() < 1e-12);
  CHECK((rod.pose * Vec3(0, 0, 0.5) - Vec3(0.5, 0, 0)).norm() < 1e-12);
  CHECK(scene.shapes(0)[1].kind == Shape::Kind::cylinder);

  const auto file = std::filesystem::temp_directory_path() / "symdyn_joint_segments.glb";
  Animation animation(model);
  animation.record(model.initial_state());
  write_glb(file, scene, animation);
  tinygltf::Model g;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  REQUIRE(loader.LoadBinaryFromFile(&g, &error, &warning, file.string()));
  REQUIRE(g.nodes.size() == 3);  // world, rod1, rod2
  const auto& primitives = g.meshes[g.nodes[1].mesh].primitives;
  REQUIRE(primitives.size() == 2);
  // The capsule's bounds in rod1's frame: the segment, and the caps' radius around it.
  const auto& bounds = g.accessors[primitives[0].attributes.at("POSITION")];
  CHECK(bounds.minValues[0] == Approx(-0.52).margin(1e-6));
  CHECK(bounds.maxValues[0] == Approx(0.52).margin(1e-6));
  CHECK(bounds.maxValues[1] == Approx(0.02).margin(1e-3));
}
