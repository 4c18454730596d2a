#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::runtime {

namespace {

using Vec3f = Eigen::Vector3f;

void add_triangle(TriangleMesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& na,
                  const Vec3f& nb, const Vec3f& nc) {
  // A ring that closes on the axis gives triangles with two equal corners: no surface.
  if (a == b || b == c || c == a) return;
  const auto first = static_cast<std::uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {a, b, c});
  m.normals.insert(m.normals.end(), {na, nb, nc});
  m.indices.insert(m.indices.end(), {first, first + 1, first + 2});
}

// A point of a profile in the (r, z) half-plane with its outward normal (nr, nz).
struct ProfilePoint {
  double r, z, nr, nz;
};

// The surface swept by a profile (from bottom to top, outside on its right as it
// rises) turned about the z axis.
TriangleMesh revolve(const std::vector<ProfilePoint>& profile, int segments) {
  TriangleMesh m;
  auto at = [&](const ProfilePoint& p, int j) {
    const double a = 2.0 * std::numbers::pi * j / segments;
    return std::pair{Vec3f(float(p.r * std::cos(a)), float(p.r * std::sin(a)), float(p.z)),
                     Vec3f(float(p.nr * std::cos(a)), float(p.nr * std::sin(a)), float(p.nz))};
  };
  for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
    for (int j = 0; j < segments; ++j) {
      const auto [a, na] = at(profile[k], j);
      const auto [b, nb] = at(profile[k], j + 1);
      const auto [c, nc] = at(profile[k + 1], j + 1);
      const auto [d, nd] = at(profile[k + 1], j);
      add_triangle(m, a, b, c, na, nb, nc);
      add_triangle(m, a, c, d, na, nc, nd);
    }
  }
  return m;
}

// A quarter circle of radius r centred on the axis at height zc, from angle
// a0 to a1 (0 is the equator, pi/2 the pole above).
void append_arc(std::vector<ProfilePoint>& profile, double r, double zc, double a0, double a1,
                int steps) {
  for (int k = 0; k <= steps; ++k) {
    const double a = a0 + (a1 - a0) * k / steps;
    // The poles exactly on the axis (cos(pi/2) is 6e-17), so that their
    // zero-area triangles are dropped rather than drawn with a random normal.
    const double c = std::abs(std::cos(a)) < 1e-12 ? 0.0 : std::cos(a);
    profile.push_back({r * c, zc + r * std::sin(a), c, std::sin(a)});
  }
}

TriangleMesh box_mesh(const Vec3& size) {
  TriangleMesh m;
  const Vec3f half = (size / 2).cast<float>();
  for (int axis = 0; axis < 3; ++axis) {
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3f n = Vec3f::Zero(), u = Vec3f::Zero(), v = Vec3f::Zero();
      n[axis] = sign;
      u[(axis + 1) % 3] = half[(axis + 1) % 3] * sign;  // u x v points along n
      v[(axis + 2) % 3] = half[(axis + 2) % 3];
      const Vec3f c = n.cwiseProduct(half);
      const Vec3f p[4] = {c - u - v, c + u - v, c + u + v, c - u + v};
      add_triangle(m, p[0], p[1], p[2], n, n, n);
      add_triangle(m, p[0], p[2], p[3], n, n, n);
    }
  }
  return m;
}

double positive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw ModelError(fmt::format("shape: {} must be positive and finite, not {}", what, value));
  }
  return value;
}

}  // namespace

void TriangleMesh::append(const TriangleMesh& other, const Eigen::Isometry3d& pose) {
  const Eigen::Isometry3f p = pose.cast<float>();
  const auto first = static_cast<std::uint32_t>(positions.size());
  for (std::size_t i = 0; i < other.positions.size(); ++i) {
    positions.push_back(p * other.positions[i]);
    normals.push_back(p.linear() * other.normals[i]);
  }
  for (const std::uint32_t i : other.indices) indices.push_back(first + i);
}

Shape Shape::box(double x, double y, double z) {
  Shape s;
  s.kind = Kind::box;
  s.size = Vec3(positive(x, "box edge x"), positive(y, "box edge y"), positive(z, "box edge z"));
  return s;
}

Shape Shape::sphere(double radius) {
  Shape s;
  s.kind = Kind::sphere;
  s.size = Vec3(positive(radius, "sphere radius"), 0, 0);
  return s;
}

Shape Shape::cylinder(double radius, double length) {
  Shape s;
  s.kind = Kind::cylinder;
  s.size = Vec3(positive(radius, "cylinder radius"), positive(length, "cylinder length"), 0);
  return s;
}

Shape Shape::capsule(double radius, double length) {
  Shape s;
  s.kind = Kind::capsule;
  s.size = Vec3(positive(radius, "capsule radius"), positive(length, "capsule length"), 0);
  return s;
}

Shape Shape::triangles(std::shared_ptr<const TriangleMesh> mesh) {
  if (!mesh || mesh->indices.empty()) throw ModelError("shape: a mesh needs triangles");
  Shape s;
  s.kind = Kind::mesh;
  s.mesh = std::move(mesh);
  return s;
}

TriangleMesh tessellate(const Shape& shape, int segments) {
  segments = std::max(segments, 3);
  const double r = shape.size.x(), half = shape.size.y() / 2;
  std::vector<ProfilePoint> profile;
  TriangleMesh local;
  switch (shape.kind) {
    case Shape::Kind::box:
      local = box_mesh(shape.size);
      break;
    case Shape::Kind::sphere:
      append_arc(profile, r, 0.0, -std::numbers::pi / 2, std::numbers::pi / 2, segments / 2);
      local = revolve(profile, segments);
      break;
    case Shape::Kind::cylinder:
      profile = {{0, -half, 0, -1}, {r, -half, 0, -1}, {r, -half, 1, 0},
                 {r, half, 1, 0},   {r, half, 0, 1},   {0, half, 0, 1}};
      local = revolve(profile, segments);
      break;
    case Shape::Kind::capsule:
      append_arc(profile, r, -half, -std::numbers::pi / 2, 0.0, segments / 4);
      append_arc(profile, r, half, 0.0, std::numbers::pi / 2, segments / 4);
      local = revolve(profile, segments);
      break;
    case Shape::Kind::mesh:
      local = *shape.mesh;
      break;
  }
  TriangleMesh placed;
  placed.append(local, shape.pose);
  return placed;
}

namespace {

// Principal moments, ascending, and their axes as a rotation (columns).
std::pair<Vec3, Mat3> principal(const Mat3& inertia) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(inertia);
  Mat3 axes = eigen.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  return {eigen.eigenvalues(), axes};
}

// A shape's local z axis turned onto `axis`.
Eigen::Isometry3d along(const Vec3& axis) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis).toRotationMatrix();
  return pose;
}

}  // namespace

Shape inertia_box(double mass, const Mat3& inertia) {
  const auto [I, axes] = principal(inertia);
  Vec3 edge;
  for (int k = 0; k < 3; ++k) {
    const double sum = I[(k + 1) % 3] + I[(k + 2) % 3] - I[k];
    edge[k] = std::sqrt(std::max(0.0, 6.0 * sum / mass));
  }
  edge = edge.cwiseMax(0.02 * edge.maxCoeff());
  Shape s = Shape::box(edge.x(), edge.y(), edge.z());
  s.pose.linear() = axes;
  return s;
}

std::optional<Shape> inertia_cylinder(double mass, const Mat3& inertia) {
  const auto [I, axes] = principal(inertia);
  const double close = 0.02 * I[2];
  const bool low_pair = I[1] - I[0] <= close, high_pair = I[2] - I[1] <= close;
  if (low_pair == high_pair) return std::nullopt;  // three distinct moments, or three equal
  const int k = low_pair ? 2 : 0;                  // the axis: the moment apart
  const double A = I[k], B = (I.sum() - A) / 2;
  double radius = std::sqrt(2.0 * A / mass);
  double length = std::sqrt(std::max(0.0, (12.0 * B - 6.0 * A) / mass));
  radius = std::max(radius, 0.02 * length);
  length = std::max(length, 0.25 * radius);
  return Shape::cylinder(radius, length).at(along(axes.col(k)));
}

Shape inertia_shape(double mass, const Mat3& inertia) {
  const Vec3 I = principal(inertia).first;
  if (I[2] <= 0.0) {  // a point mass: a ball of water's density
    return Shape::sphere(std::cbrt(3.0 * mass / (4.0 * std::numbers::pi * 1000.0)));
  }
  if (I[2] - I[0] <= 0.02 * I[2]) return Shape::sphere(std::sqrt(2.5 * I[1] / mass));
  return inertia_cylinder(mass, inertia).value_or(inertia_box(mass, inertia));
}

std::vector<std::vector<Segment>> joint_segments(const Model& model) {
  std::vector<std::vector<Segment>> out(model.nbody());
  if (!model.has_joint_points()) return out;
  const Model::JointPoints points = model.joint_points();
  double longest = 0.0;
  for (int c = 0; c < model.nbody(); ++c) {
    const int i = model.reference_body(c);
    if (i < 0) continue;
    out[i].push_back({points.joint[i], points.anchor[c]});
    longest = std::max(longest, (points.anchor[c] - points.joint[i]).norm());
  }
  for (int i = 0; i < model.nbody(); ++i) {
    if (out[i].empty()) out[i].push_back({points.joint[i], Vec3::Zero()});
    longest = std::max(longest, points.joint[i].norm());
  }
  // Rounding's lengths: a child hung at its reference's joint point, a G at the joint.
  for (auto& segments : out) {
    std::erase_if(segments,
                  [&](const Segment& s) { return !((s.to - s.from).norm() > 1e-9 * longest); });
  }
  return out;
}

std::vector<Shape> default_shapes(double mass, const Mat3& inertia,
                                  const std::vector<Segment>& segments, double radius) {
  std::vector<Shape> out;
  for (const Segment& s : segments) {
    const Vec3 d = s.to - s.from;
    Shape rod = Shape::capsule(std::min(radius, 0.1 * d.norm()), d.norm()).at(along(d));
    rod.pose.translation() = (s.from + s.to) / 2;
    out.push_back(rod);
  }
  Shape solid = inertia_shape(mass, inertia);
  if (out.empty() || solid.kind != Shape::Kind::box) out.push_back(solid);
  return out;
}

Colour body_colour(int body) {
  // Tableau's ten, muted enough to be shaded.
  static constexpr std::array<std::uint32_t, 10> rgb = {0x4e79a7, 0xf28e2b, 0x59a14f, 0xe15759,
                                                        0x76b7b2, 0xedc948, 0xb07aa1, 0xff9da7,
                                                        0x9c755f, 0xbab0ac};
  const std::uint32_t c = rgb[static_cast<std::size_t>(body) % rgb.size()];
  return {((c >> 16) & 255) / 255.0f, ((c >> 8) & 255) / 255.0f, (c & 255) / 255.0f, 1.0f};
}

Scene::Scene(const Model& model)
    : names_(model.body_names()),
      shapes_(model.nbody()),
      customized_(model.nbody(), false),
      up_(model.gravity().norm() > 0 ? Vec3(-model.gravity().normalized()) : Vec3::UnitZ()) {
  const std::vector<std::vector<Segment>> segments = joint_segments(model);
  double longest = 0.0;
  for (const auto& body : segments) {
    for (const Segment& s : body) longest = std::max(longest, (s.to - s.from).norm());
  }
  for (int i = 0; i < model.nbody(); ++i) {
    if (model.mass(i) <= 0.0) continue;  // a massless frame: nothing to see
    shapes_[i] = default_shapes(model.mass(i), model.inertia(i), segments[i], 0.02 * longest);
    for (Shape& s : shapes_[i]) s.colour = body_colour(i);
  }
}

void Scene::check_body(int body) const {
  if (body < 0 || body >= nbody()) {
    throw ModelError(fmt::format("scene: no body {} (the model has {})", body, nbody()));
  }
}

Scene& Scene::add(int body, Shape shape) {
  check_body(body);
  if (!customized_[body]) shapes_[body].clear();
  customized_[body] = true;
  shapes_[body].push_back(std::move(shape));
  return *this;
}

Scene& Scene::hide(int body) {
  check_body(body);
  shapes_[body].clear();
  customized_[body] = true;
  return *this;
}

}  // namespace symdyn::runtime
