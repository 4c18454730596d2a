#pragma once
// What the viewers draw: shapes attached to the bodies of a model.
//
// A shape has a pose in its body's frame (origin at G, the inertia's axes) and a
// colour. A body given no shape is drawn as the mechanism it is part of
// (default_shapes): slim rods from its joint point to where each of its
// children's joints start (a stick figure of the joints, as Modelica's
// MultiBody library draws), and its inertia's solid (inertia_shape) where that
// tells something: a cylinder when two principal moments are equal (a wheel,
// an axle, a rod), a ball when all three are; the box with the same principal
// moments (inertia_box),
//   a² = 6 (B + C - A)/m,  b² = 6 (A + C - B)/m,  c² = 6 (A + B - C)/m,
// only for a body without a rod to draw. Each body in a colour of its own
// (body_colour).
//
// Every shape becomes a triangle mesh (tessellate) in its body's frame; the
// writers (gltf.hpp, easyanim.hpp) place it with the body's R and x from the
// emitted positions() alone.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <symdyn/runtime/kinematics.hpp>

namespace symdyn::runtime {

class Model;

struct Colour {
  float r = 0.6f, g = 0.6f, b = 0.65f, a = 1.0f;  // each in [0, 1]
};

// Triangles with one normal per vertex (flat faces repeat their vertices).
struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside

  std::size_t triangle_count() const { return indices.size() / 3; }
  // Appends another mesh, its vertices moved by pose.
  void append(const TriangleMesh& other, const Eigen::Isometry3d& pose);
};

// A triangle mesh read from a Wavefront OBJ or an STL (ASCII or binary) file,
// chosen by the extension; ModelError naming the file and line on bad input.
TriangleMesh read_mesh(const std::filesystem::path& file);

struct Shape {
  enum class Kind { box, sphere, cylinder, capsule, mesh };
  Kind kind = Kind::box;
  // box: edge lengths along x, y, z; sphere: (radius, -, -); cylinder and
  // capsule: (radius, length, -), along the local z axis, length between the
  // end faces (cylinder) or the centres of the end caps (capsule).
  Vec3 size = Vec3::Ones();
  std::shared_ptr<const TriangleMesh> mesh;                // Kind::mesh
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // in the body's frame
  Colour colour;

  static Shape box(double x, double y, double z);
  static Shape sphere(double radius);
  static Shape cylinder(double radius, double length);
  static Shape capsule(double radius, double length);
  static Shape triangles(std::shared_ptr<const TriangleMesh> mesh);

  Shape& at(const Eigen::Isometry3d& p) {
    pose = p;
    return *this;
  }
  Shape& with(Colour c) {
    colour = c;
    return *this;
  }
};

// The triangles of a shape in its body's frame (its pose applied); curved
// surfaces with `segments` facets around.
TriangleMesh tessellate(const Shape& shape, int segments = 24);

// The box of uniform density with the mass and inertia (at G, body axes) given,
// rotated onto the inertia's principal axes. A flat or slender body (a moment
// sum that vanishes) keeps a thickness of 2 % of its largest edge, to be seen.
Shape inertia_box(double mass, const Mat3& inertia);

// The uniform cylinder with the mass and inertia given, its axis along the
// principal axis of the moment A that differs from the other two, B:
//   r² = 2 A/m,  l² = (12 B - 6 A)/m;
// null when no two moments are equal within 2 % of the largest. A disc keeps a
// thickness of a quarter of its radius, a rod a radius of 2 % of its length.
std::optional<Shape> inertia_cylinder(double mass, const Mat3& inertia);

// What a body of mass > 0 is drawn as until given shapes: its inertia
// cylinder; a ball when its three moments are equal (of water's density when
// they vanish: a point mass); else its inertia box.
Shape inertia_shape(double mass, const Mat3& inertia);

// The default colour of body i: ten colours apart from one another, in turn.
Colour body_colour(int body);

// A straight piece of a body's stick figure, in the body's frame (from G, its axes).
struct Segment {
  Vec3 from, to;
};

// The stick figure of every body (nbody lists) from the emitted joint points
// (Model::joint_points): from the body's joint point to the anchor of each
// body whose reference it is, in the order of the bodies; to its G when it has
// none. Segments of no length are left out; none for code emitted without
// joint points.
std::vector<std::vector<Segment>> joint_segments(const Model& model);

// What a body of mass > 0 is drawn as until given shapes: a capsule of the
// radius given along each of its segments, and its inertia_shape unless that
// is a box and there is a segment.
std::vector<Shape> default_shapes(double mass, const Mat3& inertia,
                                  const std::vector<Segment>& segments, double radius);

// The shapes of every body of a model: default_shapes, each in its
// body_colour, their rods 2 % as thick as the longest segment of the model
// is long (at most a tenth of their own length), until set; nothing for a
// massless body.
class Scene {
 public:
  explicit Scene(const Model& model);

  int nbody() const { return static_cast<int>(shapes_.size()); }
  const std::string& body_name(int i) const { return names_[i]; }
  const std::vector<Shape>& shapes(int body) const { return shapes_[body]; }
  // Replaces the default shape of a body on the first call, then adds to it.
  Scene& add(int body, Shape shape);
  // Draws nothing for a body (a frame of reference without matter to show).
  Scene& hide(int body);
  // The up direction of the scene, against gravity (z when there is none).
  const Vec3& up() const { return up_; }

 private:
  void check_body(int body) const;

  std::vector<std::string> names_;
  std::vector<std::vector<Shape>> shapes_;
  std::vector<bool> customized_;
  Vec3 up_;
};

}  // namespace symdyn::runtime
