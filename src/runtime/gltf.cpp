#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/gltf.hpp>

namespace symdyn::runtime {

namespace {

using json = nlohmann::json;

// glTF's numbers for component types and buffer view targets.
constexpr int float_component = 5126, uint_component = 5125;
constexpr int array_buffer = 34962, element_array_buffer = 34963;

// The JSON document and the binary chunk of a .glb as they grow.
class GlbBuilder {
 public:
  json doc;

  // A buffer view of the bytes given, 4-byte aligned as accessors require.
  int view(const void* data, std::size_t bytes, int target = 0) {
    bin_.resize((bin_.size() + 3) / 4 * 4);
    const std::size_t offset = bin_.size();
    bin_.resize(offset + bytes);
    std::memcpy(bin_.data() + offset, data, bytes);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (target) v["target"] = target;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }

  // An accessor of float vectors (n components each), with the bounds glTF
  // requires for positions and animation inputs.
  int floats(const std::vector<float>& values, int n, const char* type, int target = 0) {
    const std::size_t count = values.size() / n;
    std::vector<float> lo(n, 0.0f), hi(n, 0.0f);
    for (std::size_t k = 0; k < count; ++k) {
      for (int c = 0; c < n; ++c) {
        const float v = values[k * n + c];
        lo[c] = k ? std::min(lo[c], v) : v;
        hi[c] = k ? std::max(hi[c], v) : v;
      }
    }
    const int v = view(values.data(), values.size() * sizeof(float), target);
    doc["accessors"].push_back({{"bufferView", v},
                                {"componentType", float_component},
                                {"count", count},
                                {"type", type},
                                {"min", lo},
                                {"max", hi}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }

  int indices(const std::vector<std::uint32_t>& values) {
    const int v = view(values.data(), values.size() * sizeof(std::uint32_t), element_array_buffer);
    doc["accessors"].push_back({{"bufferView", v},
                                {"componentType", uint_component},
                                {"count", values.size()},
                                {"type", "SCALAR"}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }

  void write(std::ostream& out) {
    bin_.resize((bin_.size() + 3) / 4 * 4);
    doc["buffers"] = json::array({{{"byteLength", bin_.size()}}});
    std::string text = doc.dump();
    text.resize((text.size() + 3) / 4 * 4, ' ');  // the JSON chunk is padded with spaces
    const std::uint32_t total = 12 + 8 + text.size() + 8 + bin_.size();
    put(out, 0x46546C67u);  // "glTF"
    put(out, 2u);
    put(out, total);
    put(out, static_cast<std::uint32_t>(text.size()));
    put(out, 0x4E4F534Au);  // "JSON"
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    put(out, static_cast<std::uint32_t>(bin_.size()));
    put(out, 0x004E4942u);  // "BIN"
    out.write(bin_.data(), static_cast<std::streamsize>(bin_.size()));
  }

 private:
  static void put(std::ostream& out, std::uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);  // glTF is little-endian, as every target of symdyn
    out.write(b, 4);
  }
  std::vector<char> bin_;
};

std::vector<float> flatten(const std::vector<Eigen::Vector3f>& v) {
  std::vector<float> out;
  out.reserve(3 * v.size());
  for (const auto& p : v) out.insert(out.end(), {p.x(), p.y(), p.z()});
  return out;
}

// One primitive per shape, each with its colour as a material; null when the
// body has nothing to draw.
json body_mesh(GlbBuilder& glb, const Scene& scene, int body) {
  json primitives = json::array();
  for (const Shape& shape : scene.shapes(body)) {
    const TriangleMesh m = tessellate(shape);
    if (m.indices.empty()) continue;
    const Colour& c = shape.colour;
    json material = {{"pbrMetallicRoughness",
                      {{"baseColorFactor", {c.r, c.g, c.b, c.a}},
                       {"metallicFactor", 0.1},
                       {"roughnessFactor", 0.6}}}};
    if (c.a < 1.0f) material["alphaMode"] = "BLEND";
    glb.doc["materials"].push_back(material);
    primitives.push_back({{"attributes",
                           {{"POSITION", glb.floats(flatten(m.positions), 3, "VEC3", array_buffer)},
                            {"NORMAL", glb.floats(flatten(m.normals), 3, "VEC3", array_buffer)}}},
                          {"indices", glb.indices(m.indices)},
                          {"material", static_cast<int>(glb.doc["materials"].size()) - 1}});
  }
  if (primitives.empty()) return nullptr;
  return {{"name", scene.body_name(body)}, {"primitives", primitives}};
}

void add_channels(GlbBuilder& glb, json& anim, const Animation& animation, int body, int node,
                  int input) {
  std::vector<float> translation, rotation;
  for (std::size_t k = 0; k < animation.frames(); ++k) {
    const Vec3 x = animation.translation(k, body);
    const Eigen::Quaterniond q = animation.rotation(k, body);
    translation.insert(translation.end(), {float(x.x()), float(x.y()), float(x.z())});
    rotation.insert(rotation.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
  }
  for (const auto& [path, values, n, type] : {std::tuple{"translation", &translation, 3, "VEC3"},
                                              std::tuple{"rotation", &rotation, 4, "VEC4"}}) {
    anim["samplers"].push_back(
        {{"input", input}, {"output", glb.floats(*values, n, type)}, {"interpolation", "LINEAR"}});
    anim["channels"].push_back(
        {{"sampler", anim["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  }
}

// A glTF animation of every body node (nodes 1 ... nbody) from a clip; none
// for a single frame, a still scene.
void add_animation(GlbBuilder& glb, const Clip& clip) {
  const Animation& a = *clip.animation;
  if (a.frames() < 2) return;
  std::vector<float> times;  // from 0, as viewers expect
  for (std::size_t k = 0; k < a.frames(); ++k) times.push_back(float(a.time(k) - a.time(0)));
  json anim = {{"name", clip.name}};
  const int input = glb.floats(times, 1, "SCALAR");
  for (int i = 0; i < a.nbody(); ++i) add_channels(glb, anim, a, i, i + 1, input);
  glb.doc["animations"].push_back(anim);
}

void check_clip(const Scene& scene, const Clip& clip) {
  if (!clip.animation || clip.animation->frames() == 0) {
    throw OptionError(fmt::format("glTF: the animation '{}' has no frame", clip.name));
  }
  if (clip.animation->nbody() != scene.nbody()) {
    throw OptionError(fmt::format("glTF: the scene has {} bodies, the animation '{}' {}",
                                  scene.nbody(), clip.name, clip.animation->nbody()));
  }
}

}  // namespace

void write_glb(std::ostream& out, const Scene& scene, const std::vector<Clip>& clips) {
  if (clips.empty()) throw OptionError("glTF: no animation to write");
  for (const Clip& clip : clips) check_clip(scene, clip);
  GlbBuilder glb;
  glb.doc["asset"] = {{"version", "2.0"}, {"generator", "symdyn"}};
  const Eigen::Quaterniond up = Eigen::Quaterniond::FromTwoVectors(scene.up(), Vec3::UnitY());
  glb.doc["nodes"].push_back({{"name", "world"}, {"rotation", {up.x(), up.y(), up.z(), up.w()}}});
  glb.doc["scenes"] = json::array({{{"nodes", {0}}}});
  glb.doc["scene"] = 0;
  const Animation& first = *clips.front().animation;
  for (int i = 0; i < scene.nbody(); ++i) {
    const Vec3 x = first.translation(0, i);
    const Eigen::Quaterniond q = first.rotation(0, i);
    json node = {{"name", scene.body_name(i)},
                 {"translation", {x.x(), x.y(), x.z()}},
                 {"rotation", {q.x(), q.y(), q.z(), q.w()}}};
    if (json mesh = body_mesh(glb, scene, i); !mesh.is_null()) {
      glb.doc["meshes"].push_back(mesh);
      node["mesh"] = glb.doc["meshes"].size() - 1;
    }
    glb.doc["nodes"].push_back(node);
    glb.doc["nodes"][0]["children"].push_back(i + 1);
  }
  for (const Clip& clip : clips) add_animation(glb, clip);
  glb.write(out);
}

void write_glb(std::ostream& out, const Scene& scene, const Animation& animation) {
  write_glb(out, scene, {Clip{"motion", &animation}});
}

void write_glb(const std::filesystem::path& file, const Scene& scene,
               const std::vector<Clip>& clips) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw OptionError(fmt::format("glTF: cannot write '{}'", file.string()));
  write_glb(out, scene, clips);
  if (!out) throw OptionError(fmt::format("glTF: writing '{}' failed", file.string()));
}

void write_glb(const std::filesystem::path& file, const Scene& scene, const Animation& animation) {
  write_glb(file, scene, {Clip{"motion", &animation}});
}

}  // namespace symdyn::runtime
