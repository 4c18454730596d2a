#include "shapes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <map>
#include <memory>

#include <symdyn/runtime/errors.hpp>

#ifdef SYMDYN_HAVE_ASSIMP
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#endif

namespace symdyn::sim {

namespace {

using runtime::Shape;
using runtime::Vec3;

Vec3 vec3(const Node& n) {
  const std::vector<double> v = n.numbers(3);
  return Vec3(v[0], v[1], v[2]);
}

// "#rrggbb", "#rrggbbaa", or [r, g, b] / [r, g, b, a] each in [0, 1].
runtime::Colour colour(const Node& n) {
  std::vector<double> c;
  if (n.is_string()) {
    const std::string text = n.string();
    const bool hex = std::all_of(text.begin() + std::min<std::size_t>(1, text.size()), text.end(),
                                 [](unsigned char ch) { return std::isxdigit(ch) != 0; });
    if (!text.starts_with('#') || !hex || (text.size() != 7 && text.size() != 9)) {
      n.fail(fmt::format("expected a colour \"#rrggbb\" or \"#rrggbbaa\", found \"{}\"", text));
    }
    for (std::size_t k = 1; k < text.size(); k += 2)
      c.push_back(std::stoi(text.substr(k, 2), nullptr, 16) / 255.0);
  } else {
    const std::size_t size = n.json().is_array() ? n.json().size() : 0;
    c = n.numbers(size == 4 ? 4 : 3);
    for (std::size_t k = 0; k < c.size(); ++k) {
      if (c[k] < 0.0 || c[k] > 1.0) {
        n.elements()[k].fail(fmt::format("a colour's part is in [0, 1], not {}", c[k]));
      }
    }
  }
  if (c.size() == 3) c.push_back(1.0);
  return {float(c[0]), float(c[1]), float(c[2]), float(c[3])};
}

// The shape's frame in its body's: "origin" (from G), and "axis" (where the
// shape's z axis points) or "axes" (the shape's three axes, in body axes).
Eigen::Isometry3d pose(const Node& n) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  if (const auto origin = n.optional("origin")) p.translation() = vec3(*origin);
  if (n.has("axis") && n.has("axes")) n["axes"].fail("give \"axis\" or \"axes\", not both");
  if (const auto axis = n.optional("axis")) {
    const Vec3 z = vec3(*axis);
    if (!(z.norm() > 0.0)) axis->fail("an axis needs a length > 0");
    p.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), z).toRotationMatrix();
  }
  if (const auto axes = n.optional("axes")) {
    const auto columns = axes->elements();
    if (columns.size() != 3) axes->fail("expected 3 axes (the shape's x, y, z, in body axes)");
    runtime::Mat3 R;
    for (int c = 0; c < 3; ++c) R.col(c) = vec3(columns[static_cast<std::size_t>(c)]);
    if ((R.transpose() * R - runtime::Mat3::Identity()).norm() > 1e-6 || R.determinant() < 0) {
      axes->fail("the axes must be orthonormal and right-handed (a rotation)");
    }
    p.linear() = R;
  }
  return p;
}

// STL and OBJ by symdyn's own reader; the rest (COLLADA .dae, PLY, glTF, ...)
// through Assimp, its nodes' transforms and its unit applied, its up axis ignored
// (coordinates as written, as for STL), missing normals made smooth.
runtime::TriangleMesh read_any_mesh(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".stl" || ext == ".obj") return runtime::read_mesh(path);
#ifdef SYMDYN_HAVE_ASSIMP
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                           aiProcess_GenSmoothNormals | aiProcess_SortByPType);
  if (scene == nullptr) {
    throw runtime::ModelError(
        fmt::format("mesh '{}': {}", path.string(), importer.GetErrorString()));
  }
  runtime::TriangleMesh out;
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
    const aiMesh& m = *scene->mMeshes[k];
    if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || m.mNormals == nullptr) continue;
    const auto first = static_cast<std::uint32_t>(out.positions.size());
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      out.positions.emplace_back(m.mVertices[v].x, m.mVertices[v].y, m.mVertices[v].z);
      out.normals.emplace_back(m.mNormals[v].x, m.mNormals[v].y, m.mNormals[v].z);
    }
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      if (m.mFaces[f].mNumIndices != 3) continue;  // points and lines
      for (unsigned i = 0; i < 3; ++i) out.indices.push_back(first + m.mFaces[f].mIndices[i]);
    }
  }
  if (out.indices.empty()) {
    throw runtime::ModelError(fmt::format("mesh '{}' has no triangle", path.string()));
  }
  return out;
#else
  throw runtime::ModelError(fmt::format(
      "mesh '{}': this symdyn-sim reads STL and OBJ meshes (it was built without Assimp, "
      "which reads {} files: Debian's libassimp-dev)",
      path.string(), ext));
#endif
}

// Meshes read once per file, shared by the shapes that name it.
using MeshCache = std::map<std::filesystem::path, std::shared_ptr<const runtime::TriangleMesh>>;

Shape mesh_shape(const Node& n, const std::filesystem::path& directory, MeshCache& cache) {
  const Node file = n["file"];
  const std::filesystem::path path = directory / file.string();
  auto& mesh = cache[path];
  if (!mesh) {
    try {
      mesh = std::make_shared<const runtime::TriangleMesh>(read_any_mesh(path));
    } catch (const runtime::ModelError& e) {
      file.fail(e.what());
    }
  }
  // "scale": a number, or one per axis (a URDF mesh's); normals n / s, normalized.
  Vec3 scale = Vec3::Ones();
  if (const auto s = n.optional("scale")) {
    scale = s->is_number() ? Vec3::Constant(s->positive()) : vec3(*s);
    if (!(scale.minCoeff() > 0.0)) s->fail("a scale is > 0");
  }
  if (scale == Vec3::Ones()) return Shape::triangles(mesh);
  auto scaled = std::make_shared<runtime::TriangleMesh>(*mesh);
  const Eigen::Vector3f by = scale.cast<float>();
  for (auto& v : scaled->positions) v = v.cwiseProduct(by);
  for (auto& normal : scaled->normals) normal = normal.cwiseQuotient(by).normalized();
  return Shape::triangles(std::move(scaled));
}

Shape shape(const Node& n, const std::filesystem::path& directory, MeshCache& cache) {
  static const std::array<std::string_view, 5> types = {"box", "sphere", "cylinder", "capsule",
                                                        "mesh"};
  const std::string type = n["type"].string();
  Shape s;
  if (type == "box") {
    n.allow_only({"type", "size", "origin", "axis", "axes", "colour"});
    const Node size = n["size"];
    const Vec3 e = vec3(size);
    for (int k = 0; k < 3; ++k) {
      if (!(e[k] > 0.0)) size.fail(fmt::format("a box's edges are > 0, not {}", e[k]));
    }
    s = Shape::box(e.x(), e.y(), e.z());
  } else if (type == "sphere") {
    n.allow_only({"type", "radius", "origin", "colour"});
    s = Shape::sphere(n["radius"].positive());
  } else if (type == "cylinder" || type == "capsule") {
    n.allow_only({"type", "radius", "length", "origin", "axis", "axes", "colour"});
    const double radius = n["radius"].positive(), length = n["length"].positive();
    s = type == "cylinder" ? Shape::cylinder(radius, length) : Shape::capsule(radius, length);
  } else if (type == "mesh") {
    n.allow_only({"type", "file", "scale", "origin", "axis", "axes", "colour"});
    s = mesh_shape(n, directory, cache);
  } else {
    n["type"].fail(
        fmt::format("unknown shape type '{}' (expected: {})", type, fmt::join(types, ", ")));
  }
  s.pose = pose(n);
  return s;
}

// A file of shapes named by the scenario ("shapes": "arm_shapes.json", as
// symdyn-urdf --shapes writes), relative to the scenario.
nlohmann::json read_shapes_file(const Node& name, const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) name.fail(fmt::format("cannot read the shapes file '{}'", path.string()));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    name.fail(fmt::format("the shapes file '{}' is not JSON: {}", path.string(), e.what()));
  }
}

void add_shapes(runtime::Scene& scene, const Node& shapes, const runtime::Model& model,
                const std::filesystem::path& directory) {
  MeshCache cache;
  for (const auto& [name, value] : shapes.members()) {
    const auto& bodies = model.body_names();
    const auto found = std::find(bodies.begin(), bodies.end(), name);
    if (found == bodies.end()) {
      value.fail(fmt::format("unknown body '{}' (bodies: {})", name, fmt::join(bodies, ", ")));
    }
    const int body = static_cast<int>(found - bodies.begin());
    if (!value.is_object() && !value.json().is_array()) {
      value.fail("expected a shape (an object) or a list of shapes");
    }
    const std::vector<Node> list = value.is_object() ? std::vector<Node>{value} : value.elements();
    if (list.empty()) scene.hide(body);
    for (const Node& n : list) {
      Shape s = shape(n, directory, cache);
      s.colour = n.has("colour") ? colour(n["colour"]) : runtime::body_colour(body);
      scene.add(body, std::move(s));
    }
  }
}

}  // namespace

runtime::Scene read_scene(const Scenario& scenario, const runtime::Model& model) {
  runtime::Scene scene(model);
  const auto shapes = scenario.root().optional("shapes");
  if (!shapes) return scene;
  if (!shapes->is_string()) {
    add_shapes(scene, *shapes, model, scenario.directory);
    return scene;
  }
  const std::filesystem::path path = scenario.directory / shapes->string();
  const nlohmann::json document = read_shapes_file(*shapes, path);
  add_shapes(scene, Node(document, path.string()), model, path.parent_path());
  return scene;
}

}  // namespace symdyn::sim
