#include "overrides.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "elements.hpp"

namespace symdyn::sim {

namespace {

using nlohmann::json;

std::vector<std::string> split(std::string_view path) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = path.find('.', begin);
    parts.emplace_back(
        path.substr(begin, dot == std::string_view::npos ? std::string_view::npos : dot - begin));
    if (dot == std::string_view::npos) return parts;
    begin = dot + 1;
  }
}

std::string listed(const std::vector<std::string>& names) {
  return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// An object member of the document, made when missing; the scenario's value
// must be an object if it is there.
json& object_member(json& parent, const std::string& key, std::string_view path) {
  json& member = parent[key];
  if (member.is_null()) member = json::object();
  if (!member.is_object())
    throw OverrideError(std::string(path),
                        fmt::format("the scenario's '{}' is not an object", key));
  return member;
}

// The value the path names in `document` (made when its parents and the value
// are absent but allowed), or ScenarioError.
json& slot(json& document, std::string_view path, const runtime::Model& model) {
  const std::vector<std::string> p = split(path);
  const auto fail = [&](const std::string& what) -> json& {
    throw OverrideError(std::string(path), what);
  };
  const auto size = [&](std::size_t n, const char* form) {
    if (p.size() != n) fail(fmt::format("expected {}", form));
  };
  const std::string& head = p[0];
  if (head == "t_end" || head == "output_interval") {
    size(1, head.c_str());
    return document[head];
  }
  if (head == "parameters") {
    size(2, "parameters.<name>");
    if (!contains(model.param_names(), p[1])) {
      fail(fmt::format("unknown parameter '{}' (parameters of {}: {})", p[1], model.name(),
                       listed(model.param_names())));
    }
    return object_member(document, "parameters", path)[p[1]];
  }
  if (head == "initial") {
    size(3, "initial.q.<coordinate> or initial.qd.<coordinate>");
    if (p[1] != "q" && p[1] != "qd")
      fail(fmt::format("unknown part '{}' (expected q or qd)", p[1]));
    if (!contains(model.q_names(), p[2])) {
      fail(fmt::format("unknown coordinate '{}' (coordinates: {})", p[2], listed(model.q_names())));
    }
    return object_member(object_member(document, "initial", path), p[1], path)[p[2]];
  }
  if (head == "variables") {
    size(2, "variables.<name>");
    std::vector<std::string> declared;
    if (document.contains("variables") && document["variables"].is_object()) {
      for (const auto& [name, value] : document["variables"].items()) declared.push_back(name);
    }
    if (!contains(declared, p[1])) {
      fail(fmt::format("the scenario declares no variable '{}' (variables: {})", p[1],
                       listed(declared)));
    }
    return document["variables"][p[1]];
  }
  if (head == "integrator") {
    size(2, "integrator.<name, tolerance, rtol, atol or step>");
    if (!contains({"name", "tolerance", "rtol", "atol", "step"}, p[1])) {
      fail(fmt::format("unknown part '{}' (expected name, tolerance, rtol, atol or step)", p[1]));
    }
    json& integrator = document["integrator"];
    if (integrator.is_string()) integrator = json{{"name", integrator.get<std::string>()}};
    if (integrator.is_null()) integrator = json::object();
    if (!integrator.is_object()) fail("the scenario's integrator is neither a name nor an object");
    if (p[1] == "tolerance") {
      integrator.erase("rtol");
      integrator.erase("atol");
    }
    return integrator[p[1]];
  }
  if (head == "forces") {
    if (p.size() < 3) fail("expected forces.<element>.<member>");
    std::vector<std::string> names;
    json* element = nullptr;
    if (document.contains("forces") && document["forces"].is_array()) {
      for (json& e : document["forces"]) {
        if (!e.is_object() || !e.contains("name") || !e["name"].is_string()) continue;
        names.push_back(e["name"].get<std::string>());
        if (names.back() == p[1]) element = &e;
      }
    }
    if (element == nullptr)
      fail(fmt::format("no force element '{}' (elements: {})", p[1], listed(names)));
    const std::string type = element->contains("type") && (*element)["type"].is_string()
                                 ? (*element)["type"].get<std::string>()
                                 : std::string();
    const std::vector<std::string> members = element_members(type);
    if (!contains(members, p[2])) {
      fail(fmt::format("a {} has no member '{}' (members: {})", type, p[2], listed(members)));
    }
    json* at = &(*element)[p[2]];
    for (std::size_t k = 3; k < p.size(); ++k) {
      const std::string so_far =
          fmt::format("{}", fmt::join(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(k), "."));
      if (at->is_object()) {
        if (!at->contains(p[k])) fail(fmt::format("{} has no member '{}'", so_far, p[k]));
        at = &(*at)[p[k]];
      } else if (at->is_array()) {
        std::size_t index = 0;
        const auto [end, ec] = std::from_chars(p[k].data(), p[k].data() + p[k].size(), index);
        if (ec != std::errc() || end != p[k].data() + p[k].size() || index >= at->size()) {
          fail(fmt::format("{} has {} entries: '{}' is not an index among them", so_far, at->size(),
                           p[k]));
        }
        at = &(*at)[index];
      } else {
        fail(fmt::format("{} is {} in the scenario: it has no parts", so_far,
                         at->is_null() ? "absent" : "a single value"));
      }
    }
    return *at;
  }
  return fail(fmt::format(
      "unknown part '{}' (expected parameters, initial, variables, forces, integrator, t_end or "
      "output_interval)",
      head));
}

}  // namespace

OverrideError::OverrideError(std::string path, std::string detail)
    : ScenarioError(fmt::format("{}: {}", path, detail)),
      path_(std::move(path)),
      detail_(std::move(detail)) {}

Override parse_override(std::string_view assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    throw ScenarioError(
        fmt::format("--set '{}': expected path=value (forces.spring.stiffness=2e4)", assignment));
  }
  Override o{std::string(assignment.substr(0, eq)), {}};
  const std::string_view text = assignment.substr(eq + 1);
  o.value = json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (o.value.is_discarded()) o.value = std::string(text);
  return o;
}

void check_override(const Scenario& scenario, const runtime::Model& model, std::string_view path) {
  json copy = scenario.document;
  slot(copy, path, model);
}

Scenario with_overrides(const Scenario& scenario, const runtime::Model& model,
                        const std::vector<Override>& overrides) {
  json document = scenario.document;
  for (const Override& o : overrides) slot(document, o.path, model) = o.value;
  Scenario changed =
      scenario_from_document(std::move(document), scenario.origin, scenario.directory);
  changed.name = scenario.name;
  return changed;
}

}  // namespace symdyn::sim
