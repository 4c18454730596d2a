#include "scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "module.hpp"

namespace symdyn::sim {

namespace {

std::string type_name(const nlohmann::json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_boolean()) return "true or false";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return "null";
}

// JSON Pointer escaping of a key.
std::string escaped(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

void Node::fail(const std::string& what) const { throw ScenarioError(where() + ": " + what); }

void Node::allow_only(std::initializer_list<std::string_view> keys) const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  for (const auto& [key, value] : value_->items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      Node(value, origin_, path_ + "/" + escaped(key))
          .fail(fmt::format("unknown key '{}' (expected: {})", key, fmt::join(keys, ", ")));
    }
  }
}

bool Node::has(std::string_view key) const { return value_->is_object() && value_->contains(key); }

Node Node::operator[](std::string_view key) const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  const auto it = value_->find(key);
  if (it == value_->end()) fail(fmt::format("missing key '{}'", key));
  return Node(*it, origin_, path_ + "/" + escaped(key));
}

std::optional<Node> Node::optional(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

std::vector<std::pair<std::string, Node>> Node::members() const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  std::vector<std::pair<std::string, Node>> out;
  for (const auto& [key, value] : value_->items()) out.emplace_back(key, Node(value, origin_, path_ + "/" + escaped(key)));
  return out;
}

std::vector<Node> Node::elements() const {
  if (!value_->is_array()) fail(fmt::format("expected an array, found {}", type_name(*value_)));
  std::vector<Node> out;
  for (std::size_t i = 0; i < value_->size(); ++i) out.emplace_back((*value_)[i], origin_, fmt::format("{}/{}", path_, i));
  return out;
}

std::string Node::string() const {
  if (!value_->is_string()) fail(fmt::format("expected a string, found {}", type_name(*value_)));
  return value_->get<std::string>();
}

double Node::number() const {
  if (!value_->is_number()) fail(fmt::format("expected a number, found {}", type_name(*value_)));
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("expected a finite number");
  return v;
}

double Node::positive() const {
  const double v = number();
  if (!(v > 0.0)) fail(fmt::format("expected a number > 0, found {}", v));
  return v;
}

bool Node::boolean() const {
  if (!value_->is_boolean()) fail(fmt::format("expected true or false, found {}", type_name(*value_)));
  return value_->get<bool>();
}

std::vector<double> Node::numbers(std::size_t n) const {
  if (!value_->is_array() || value_->size() != n) {
    fail(fmt::format("expected an array of {} numbers, found {}", n,
                     value_->is_array() ? fmt::format("{} entries", value_->size()) : type_name(*value_)));
  }
  std::vector<double> out;
  for (const Node& e : elements()) out.push_back(e.number());
  return out;
}

double Node::number_or(std::string_view key, double fallback) const {
  const auto n = optional(key);
  return n ? n->number() : fallback;
}

std::string Node::string_or(std::string_view key, std::string fallback) const {
  const auto n = optional(key);
  return n ? n->string() : fallback;
}

namespace {

// model: "name" | {"name", "variant", "module"}
void read_model(const Node& root, Scenario& s) {
  const Node m = root["model"];
  if (m.is_string()) {
    s.model = m.string();
    return;
  }
  m.allow_only({"name", "variant", "module"});
  s.model = m["name"].string();
  s.variant = m.string_or("variant", "");
  s.module = m.string_or("module", "");
}

// integrator: "name" | {"name", "tolerance", "rtol", "atol", "step"}
void read_integrator(const Node& root, Scenario& s) {
  const auto i = root.optional("integrator");
  if (!i) return;
  if (i->is_string()) {
    s.integrator = i->string();
    return;
  }
  i->allow_only({"name", "tolerance", "rtol", "atol", "step"});
  s.integrator = i->string_or("name", s.integrator);
  if (const auto t = i->optional("tolerance")) s.rtol = s.atol = t->positive();
  if (const auto t = i->optional("rtol")) s.rtol = t->positive();
  if (const auto t = i->optional("atol")) s.atol = t->positive();
  if (const auto t = i->optional("step")) s.step = t->positive();
}

void read_event_times(const Node& root, Scenario& s) {
  const auto events = root.optional("events");
  if (!events) return;
  for (const Node& e : events->elements()) {
    const Node t = e["time"];
    const double time = t.number();
    if (!(time > 0.0 && time < s.t_end)) t.fail(fmt::format("expected a time inside (0, t_end = {}), found {}", s.t_end, time));
    s.event_times.push_back(time);
  }
  std::sort(s.event_times.begin(), s.event_times.end());
}

}  // namespace

Scenario parse_scenario(std::string_view text, std::string origin, std::filesystem::path directory) {
  Scenario s;
  s.origin = std::move(origin);
  s.directory = std::move(directory);
  try {
    s.document = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    // e.what() reads "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    // (or out_of_range.406 for a number too large for a double)
    std::string what = e.what();
    const auto at = what.find("] ");
    throw ScenarioError(fmt::format("{}: not JSON: {}", s.origin, at == std::string::npos ? what : what.substr(at + 2)));
  }
  const Node root = s.root();
  root.allow_only({"$schema", "description", "model", "parameters", "initial", "variables", "forces", "events",
                   "integrator", "t_end", "output_interval", "outputs", "checks"});
  s.description = root.string_or("description", "");
  read_model(root, s);
  if (const auto t = root.optional("t_end")) s.t_end = t->positive();
  if (const auto t = root.optional("output_interval")) s.output_interval = t->positive();
  read_integrator(root, s);
  read_event_times(root, s);
  return s;
}

Scenario load_scenario(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ScenarioError(fmt::format("cannot read scenario file '{}'", file.string()));
  std::stringstream text;
  text << in.rdbuf();
  Scenario s = parse_scenario(text.str(), file.string(), file.parent_path());
  s.name = file.stem().string();
  return s;
}

runtime::Model make_model(const Scenario& scenario, std::string_view variant) {
  const std::string wanted(variant.empty() ? scenario.variant : variant);
  if (!scenario.module.empty()) {
    const std::filesystem::path path = scenario.directory / scenario.module;
    runtime::Model m = load_model_module(path, scenario.model);
    if (!wanted.empty() && m.variant() != wanted) {
      scenario.root()["model"]["variant"].fail(
          fmt::format("the module '{}' holds variant '{}', not '{}'", path.string(), m.variant(), wanted));
    }
    return m;
  }
  std::vector<std::string> variants, models;
  for (const auto& b : builtin_models()) {
    if (b.model != scenario.model) {
      if (std::find(models.begin(), models.end(), b.model) == models.end()) models.push_back(b.model);
      continue;
    }
    if (wanted.empty() || b.variant == wanted) return b.make();
    variants.push_back(b.variant);
  }
  if (variants.empty()) {
    throw ScenarioError(fmt::format("{}: /model: no built-in model '{}' (built in: {}); a model of your own needs "
                                    "\"module\"",
                                    scenario.origin, scenario.model, fmt::join(models, ", ")));
  }
  throw ScenarioError(fmt::format("model '{}' has no variant '{}' (built variants: {})", scenario.model, wanted,
                                  fmt::join(variants, ", ")));
}

}  // namespace symdyn::sim
