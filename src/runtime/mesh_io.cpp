// Triangle meshes from Wavefront OBJ and STL files (scene.hpp's read_mesh).
// Faces are flat-shaded: each triangle gets its own vertices and normal.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::runtime {

namespace {

using Vec3f = Eigen::Vector3f;

void add_flat_triangle(TriangleMesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3f n = (b - a).cross(c - a).normalized();
  if (!n.allFinite()) return;  // degenerate: no area, no normal
  const auto first = static_cast<std::uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {a, b, c});
  m.normals.insert(m.normals.end(), {n, n, n});
  m.indices.insert(m.indices.end(), {first, first + 1, first + 2});
}

[[noreturn]] void fail(const std::filesystem::path& file, std::size_t line,
                       const std::string& what) {
  throw ModelError(fmt::format("mesh '{}'{}: {}", file.string(),
                               line ? fmt::format(", line {}", line) : "", what));
}

// OBJ: "v x y z" vertices, "f i j k ..." faces (1-based, negative from the end,
// "i/t/n" forms), polygons split into fans. Other statements are ignored.
TriangleMesh read_obj(const std::filesystem::path& file, std::istream& in) {
  std::vector<Vec3f> vertices;
  TriangleMesh m;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::istringstream words(text);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      Vec3f v;
      if (!(words >> v.x() >> v.y() >> v.z()) || !v.allFinite())
        fail(file, line, "a vertex needs three finite numbers");
      vertices.push_back(v);
    } else if (keyword == "f") {
      std::vector<Vec3f> corners;
      for (std::string ref; words >> ref;) {
        long i = 0;
        try {
          i = std::stol(ref.substr(0, ref.find('/')));
        } catch (const std::exception&) {
          fail(file, line, fmt::format("'{}' is not a vertex index", ref));
        }
        const long n = static_cast<long>(vertices.size());
        const long index = i < 0 ? n + i : i - 1;
        if (i == 0 || index < 0 || index >= n) {
          fail(file, line, fmt::format("vertex {} does not exist ({} vertices so far)", i, n));
        }
        corners.push_back(vertices[index]);
      }
      if (corners.size() < 3) fail(file, line, "a face needs at least three vertices");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        add_flat_triangle(m, corners[0], corners[k], corners[k + 1]);
      }
    }
  }
  return m;
}

// ASCII STL: "vertex x y z" lines, three per facet.
TriangleMesh read_ascii_stl(const std::filesystem::path& file, std::istream& in) {
  TriangleMesh m;
  std::vector<Vec3f> corners;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::istringstream words(text);
    std::string keyword;
    words >> keyword;
    if (keyword == "vertex") {
      Vec3f v;
      if (!(words >> v.x() >> v.y() >> v.z()) || !v.allFinite())
        fail(file, line, "a vertex needs three finite numbers");
      corners.push_back(v);
    } else if (keyword == "endfacet") {
      if (corners.size() != 3) fail(file, line, "a facet needs three vertices");
      add_flat_triangle(m, corners[0], corners[1], corners[2]);
      corners.clear();
    }
  }
  return m;
}

// Binary STL: an 80-byte header, a triangle count, then 50 bytes per triangle
// (normal, three vertices as little-endian floats, two attribute bytes).
TriangleMesh read_binary_stl(const std::filesystem::path& file, const std::string& bytes) {
  if (bytes.size() < 84)
    fail(file, 0, fmt::format("{} bytes: too short for a binary STL (84 at least)", bytes.size()));
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50 * std::size_t{count}) {
    fail(file, 0,
         fmt::format("binary STL of {} triangles must be {} bytes, not {}", count,
                     84 + 50 * std::size_t{count}, bytes.size()));
  }
  TriangleMesh m;
  for (std::uint32_t t = 0; t < count; ++t) {
    float f[12];
    std::memcpy(f, bytes.data() + 84 + 50 * std::size_t{t}, sizeof f);
    add_flat_triangle(m, Vec3f(f[3], f[4], f[5]), Vec3f(f[6], f[7], f[8]),
                      Vec3f(f[9], f[10], f[11]));
  }
  return m;
}

std::string lowercase_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, 0, "cannot be read");
  const std::string ext = lowercase_extension(file);
  TriangleMesh m;
  if (ext == ".obj") {
    m = read_obj(file, in);
  } else if (ext == ".stl") {
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // "solid" starts ASCII files, and some binary headers too: trust the size first.
    std::uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    const bool binary = bytes.size() >= 84 && bytes.size() == 84 + 50 * std::size_t{count};
    std::istringstream text(bytes);
    m = binary || bytes.rfind("solid", 0) != 0 ? read_binary_stl(file, bytes)
                                               : read_ascii_stl(file, text);
  } else {
    fail(file, 0, "unknown format (OBJ or STL expected, by the extension .obj or .stl)");
  }
  if (m.indices.empty()) fail(file, 0, "has no triangle");
  return m;
}

}  // namespace symdyn::runtime
