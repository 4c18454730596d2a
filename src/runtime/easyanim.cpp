#include <fmt/format.h>
#include <fmt/os.h>

#include <array>
#include <map>

#include <symdyn/runtime/easyanim.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

namespace {

// The scene as EasyAnim sees it: nodes fixed to bodies, triangles between them.
struct Wireframe {
  struct Node {
    int body;
    Vec3 local;  // in the body's frame
  };
  struct Face {
    std::array<std::size_t, 3> nodes;
    int colour;
  };
  std::vector<Node> nodes;
  std::vector<Face> faces;
};

// Shared corners become one node (the tessellation repeats them for its normals).
Wireframe wireframe(const Scene& scene) {
  Wireframe w;
  for (int body = 0; body < scene.nbody(); ++body) {
    for (const Shape& shape : scene.shapes(body)) {
      const TriangleMesh m = tessellate(shape);
      std::map<std::array<float, 3>, std::size_t> numbers;
      auto node = [&](std::uint32_t vertex) {
        const Eigen::Vector3f& p = m.positions[vertex];
        auto [it, added] = numbers.try_emplace({p.x(), p.y(), p.z()}, w.nodes.size());
        if (added) w.nodes.push_back({body, p.cast<double>()});
        return it->second;
      };
      for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        w.faces.push_back(
            {{node(m.indices[3 * t]), node(m.indices[3 * t + 1]), node(m.indices[3 * t + 2])},
             easyanim_colour(shape.colour)});
      }
    }
  }
  return w;
}

void write_vol(const std::filesystem::path& file, const Wireframe& w,
               const std::vector<Vec3>& first, const std::string& title) {
  auto out = fmt::output_file(file.string());
  out.print("{}\n{}\n", title, w.nodes.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    out.print("{} {} {} {}\n", i, first[i].x(), first[i].y(), first[i].z());
  }
  out.print("0\n{}\n", w.faces.size());
  for (std::size_t f = 0; f < w.faces.size(); ++f) {
    const auto& face = w.faces[f];
    out.print("{} 3 {} {} {} {}\n", f, face.nodes[0], face.nodes[1], face.nodes[2], face.colour);
  }
}

std::vector<Vec3> node_positions(const Wireframe& w, const Animation& animation,
                                 std::size_t frame) {
  std::vector<Vec3> p;
  p.reserve(w.nodes.size());
  for (const auto& n : w.nodes) {
    p.push_back(animation.R(frame, n.body) * n.local + animation.translation(frame, n.body));
  }
  return p;
}

std::filesystem::path with_extension(std::filesystem::path stem, const char* ext) {
  stem += ext;
  return stem;
}

}  // namespace

int easyanim_colour(const Colour& c) {
  static constexpr std::array<std::array<float, 3>, 16> ega = {{
      {0, 0, 0},
      {0, 0, 0.67f},
      {0, 0.67f, 0},
      {0, 0.67f, 0.67f},
      {0.67f, 0, 0},
      {0.67f, 0, 0.67f},
      {0.67f, 0.33f, 0},
      {0.67f, 0.67f, 0.67f},
      {0.33f, 0.33f, 0.33f},
      {0.33f, 0.33f, 1},
      {0.33f, 1, 0.33f},
      {0.33f, 1, 1},
      {1, 0.33f, 0.33f},
      {1, 0.33f, 1},
      {1, 1, 0.33f},
      {1, 1, 1},
  }};
  int best = 0;
  float best_distance = 1e9f;
  for (int i = 0; i < 16; ++i) {
    const float d = (c.r - ega[i][0]) * (c.r - ega[i][0]) + (c.g - ega[i][1]) * (c.g - ega[i][1]) +
                    (c.b - ega[i][2]) * (c.b - ega[i][2]);
    if (d < best_distance) best_distance = d, best = i;
  }
  return best;
}

void write_easyanim(const std::filesystem::path& stem, const Scene& scene,
                    const Animation& animation, const std::string& title) {
  if (animation.frames() == 0) throw OptionError("EasyAnim: the animation has no frame");
  const Wireframe w = wireframe(scene);
  write_vol(with_extension(stem, ".vol"), w, node_positions(w, animation, 0), title);
  auto van = fmt::output_file(with_extension(stem, ".van").string());
  for (std::size_t k = 0; k < animation.frames(); ++k) {
    for (const Vec3& p : node_positions(w, animation, k))
      van.print("{} {} {}\n", p.x(), p.y(), p.z());
  }
}

void write_easyanim_modes(const std::filesystem::path& stem, const Scene& scene, const Model& model,
                          const State& reference, const Linearization& lin,
                          const std::vector<Mode>& modes, double amplitude,
                          const std::string& title) {
  const Wireframe w = wireframe(scene);
  Kinematics k = model.make_kinematics();
  auto positions_at = [&](const Vector& q) {
    model.positions(reference.t, q.data(), k);
    std::vector<Vec3> p;
    for (const auto& n : w.nodes) p.push_back(k.R(n.body) * n.local + k.x(n.body));
    return p;
  };
  write_vol(with_extension(stem, ".vol"), w, positions_at(reference.q), title);
  auto vmo = fmt::output_file(with_extension(stem, ".vmo").string());
  for (const Mode& mode : modes) {
    const double largest = mode.shape.cwiseAbs().maxCoeff();
    const double scale = largest > 0 ? amplitude / largest : 0.0;
    vmo.print("{} {} {} {}\n", mode.pole.real(), mode.pole.imag(), mode.natural_frequency_hz,
              mode.damping_ratio);
    for (const bool imaginary : {false, true}) {
      Vector q = reference.q;
      for (std::size_t j = 0; j < lin.kept.size(); ++j) {
        const std::complex<double> psi = mode.shape[static_cast<Eigen::Index>(j)];
        q[lin.kept[j]] += scale * (imaginary ? psi.imag() : psi.real());
      }
      for (const Vec3& p : positions_at(q)) vmo.print("{} {} {}\n", p.x(), p.y(), p.z());
    }
  }
}

}  // namespace symdyn::runtime
