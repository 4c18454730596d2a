#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/html_viewer.hpp>
#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

namespace detail {
// The viewer's script in chunks, ending with nullptr (generated at build time
// from viewer/ by cmake/EmbedText.cmake; empty without npm).
extern const char* const viewer_bundle[];
}  // namespace detail

namespace {

std::string base64(const std::string& bytes) {
  static constexpr char digits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = v << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

// JSON inside a <script> element: "</" would end the element early.
std::string script_safe(std::string text) {
  for (std::size_t at = 0; (at = text.find("</", at)) != std::string::npos; at += 3)
    text.replace(at, 2, "<\\/");
  return text;
}

void check_series(const TimeSeries& series) {
  if (series.names.size() != series.columns.size()) {
    throw OptionError(fmt::format("HTML viewer: {} series names for {} columns",
                                  series.names.size(), series.columns.size()));
  }
  if (!series.units.empty() && series.units.size() != series.names.size()) {
    throw OptionError(fmt::format("HTML viewer: {} series units for {} names", series.units.size(),
                                  series.names.size()));
  }
  for (std::size_t k = 1; k < series.columns.size(); ++k) {
    if (series.columns[k].size() != series.columns[0].size()) {
      throw OptionError(fmt::format("HTML viewer: series '{}' has {} values, the time {}",
                                    series.names[k], series.columns[k].size(),
                                    series.columns[0].size()));
    }
  }
}

void check_arrows(const Arrows& arrows, const TimeSeries& series) {
  const std::size_t n = arrows.names.size(),
                    values = 3 * (series.columns.empty() ? 0 : series.columns[0].size());
  if (arrows.points.size() != n || arrows.vectors.size() != n) {
    throw OptionError(fmt::format("HTML viewer: {} arrow names for {} points and {} vectors", n,
                                  arrows.points.size(), arrows.vectors.size()));
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (arrows.points[k].size() != values || arrows.vectors[k].size() != values) {
      throw OptionError(
          fmt::format("HTML viewer: arrow '{}' has {} point and {} vector values, 3 per time ({})",
                      arrows.names[k], arrows.points[k].size(), arrows.vectors[k].size(), values));
    }
  }
}

}  // namespace

std::vector<std::string> coordinate_units(const Model& model) {
  if (!model.has_positions() && !model.has_velocities()) return {};
  const State s = model.initial_state();
  Kinematics base = model.make_kinematics(), moved = model.make_kinematics();
  model.positions(s.t, s.q.data(), base);
  std::vector<std::string> units;
  for (int j = 0; j < model.nq(); ++j) {
    Vector q = s.q;
    q[j] += 1e-3;
    model.positions(s.t, q.data(), moved);
    bool turns = false;
    for (int i = 0; i < model.nbody(); ++i) turns = turns || (moved.R(i) - base.R(i)).norm() > 1e-9;
    units.push_back(turns ? "rad" : "m");
  }
  return units;
}

bool html_viewer_available() {
  return detail::viewer_bundle[0] != nullptr;
}

void write_html(const std::filesystem::path& file, const std::string& title, const Scene& scene,
                const std::vector<Clip>& clips, const TimeSeries& series, const Arrows& arrows) {
  if (!html_viewer_available()) {
    throw OptionError(
        "HTML viewer: this runtime was built without it (npm was not found when it was built)");
  }
  check_series(series);
  check_arrows(arrows, series);
  std::ostringstream glb;
  write_glb(glb, scene, clips);
  const nlohmann::json data = {
      {"title", title},
      {"glb", base64(glb.str())},
      {"series", {{"names", series.names}, {"columns", series.columns}, {"units", series.units}}},
      {"arrows",
       {{"names", arrows.names}, {"points", arrows.points}, {"vectors", arrows.vectors}}}};
  std::ofstream out(file, std::ios::binary);
  if (!out) throw OptionError(fmt::format("HTML viewer: cannot write '{}'", file.string()));
  out << "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<title>symdyn</title>\n</head>\n<body>\n<script id=\"symdyn-data\" "
         "type=\"application/json\">"
      << script_safe(data.dump()) << "</script>\n<script>\n";
  for (const char* const* chunk = detail::viewer_bundle; *chunk; ++chunk) out << *chunk;
  out << "\n</script>\n</body>\n</html>\n";
  if (!out) throw OptionError(fmt::format("HTML viewer: writing '{}' failed", file.string()));
}

}  // namespace symdyn::runtime
