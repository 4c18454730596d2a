#include "scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
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

// Names the force element or check the path is inside: " (force element 'strut')".
std::string Node::where() const {
  std::string out = origin_ + ": " + (path_.empty() ? "/" : path_);
  for (const auto& [list, kind] : {std::pair{"forces", "force element"}, {"checks", "check"}}) {
    const std::string prefix = fmt::format("/{}/", list);
    if (!path_.starts_with(prefix)) continue;
    std::size_t index = 0;
    const char* first = path_.data() + prefix.size();
    const char* last = path_.data() + path_.size();
    const auto [end, ec] = std::from_chars(first, last, index);
    if (ec != std::errc() || (end != last && *end != '/') || !root_->is_object()) break;
    const auto items = root_->find(list);
    if (items == root_->end() || !items->is_array() || index >= items->size()) break;
    const nlohmann::json& item = (*items)[index];
    if (item.is_object() && item.contains("name") && item["name"].is_string()) {
      out += fmt::format(" ({} '{}')", kind, item["name"].get<std::string>());
    }
  }
  return out;
}

void Node::fail(const std::string& what) const {
  throw ScenarioError(where() + ": " + what);
}

void Node::allow_only(std::initializer_list<std::string_view> keys) const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  for (const auto& [key, value] : value_->items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      child(value, escaped(key))
          .fail(fmt::format("unknown key '{}' (expected: {})", key, fmt::join(keys, ", ")));
    }
  }
}

bool Node::has(std::string_view key) const {
  return value_->is_object() && value_->contains(key);
}

Node Node::operator[](std::string_view key) const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  const auto it = value_->find(key);
  if (it == value_->end()) fail(fmt::format("missing key '{}'", key));
  return child(*it, escaped(key));
}

std::optional<Node> Node::optional(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

std::vector<std::pair<std::string, Node>> Node::members() const {
  if (!value_->is_object()) fail(fmt::format("expected an object, found {}", type_name(*value_)));
  std::vector<std::pair<std::string, Node>> out;
  for (const auto& [key, value] : value_->items())
    out.emplace_back(key, child(value, escaped(key)));
  return out;
}

std::vector<Node> Node::elements() const {
  if (!value_->is_array()) fail(fmt::format("expected an array, found {}", type_name(*value_)));
  std::vector<Node> out;
  for (std::size_t i = 0; i < value_->size(); ++i)
    out.push_back(child((*value_)[i], std::to_string(i)));
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
  if (!value_->is_boolean())
    fail(fmt::format("expected true or false, found {}", type_name(*value_)));
  return value_->get<bool>();
}

std::vector<double> Node::numbers(std::size_t n) const {
  if (!value_->is_array() || value_->size() != n) {
    fail(fmt::format(
        "expected an array of {} numbers, found {}", n,
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

// Reads a JSON text through nlohmann's SAX interface, to see what its DOM
// parser hides: a key given twice in an object (the DOM keeps the last
// value), a number that underflows to 0, and where in the document a parse
// error is.
class DocumentReader : public nlohmann::json_sax<nlohmann::json> {
 public:
  using json = nlohmann::json;

  bool null() override { return add(json(nullptr)); }
  bool boolean(bool v) override { return add(json(v)); }
  bool number_integer(number_integer_t v) override { return add(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return add(json(v)); }
  bool number_float(number_float_t v, const string_t& text) override {
    // 1e-400 reads as 0: a stiffness written so would silently be none.
    const std::string mantissa = text.substr(0, text.find_first_of("eE"));
    if (v == 0.0 && mantissa.find_first_of("123456789") != std::string::npos && !problem) {
      problem = {next_path(),
                 fmt::format("{} is too small for a double (it would read as 0)", text)};
    }
    return add(json(v));
  }
  bool string(string_t& v) override { return add(json(std::move(v))); }
  bool binary(binary_t& v) override { return add(json(json::binary_t(std::move(v)))); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    Level& top = levels_.back();
    if (top.container->contains(k) && !problem) {
      problem = {
          path() + "/" + escaped(k),
          fmt::format("key '{}' is given twice in this object (a JSON reader keeps one of them)",
                      k)};
    }
    top.key = std::move(k);
    top.pending = true;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t position, const std::string& /*token*/,
                   const json::exception& e) override {
    error = Error{next_path(), position, e.id, e.what()};
    return false;
  }

  json document;
  // The first duplicate key or underflow: its JSON path and what is wrong.
  std::optional<std::pair<std::string, std::string>> problem;
  struct Error {
    std::string path;
    std::size_t position = 0;  // just past the text that failed
    int id = 0;
    std::string what;
  };
  std::optional<Error> error;

 private:
  struct Level {
    json* container;
    std::string path;      // of the container
    std::string key;       // of an object: the member being read
    bool pending = false;  // its key read, its value not yet
  };

  std::string path() const { return levels_.empty() ? "" : levels_.back().path; }
  // The path of the value being read.
  std::string next_path() const {
    if (levels_.empty()) return "";
    const Level& top = levels_.back();
    if (top.container->is_array()) return top.path + "/" + std::to_string(top.container->size());
    return top.pending ? top.path + "/" + escaped(top.key) : top.path;
  }
  json* place(json&& v) {
    if (levels_.empty()) {
      document = std::move(v);
      return &document;
    }
    Level& top = levels_.back();
    if (top.container->is_array()) {
      top.container->push_back(std::move(v));
      return &top.container->back();
    }
    json& slot = (*top.container)[top.key];
    slot = std::move(v);
    top.pending = false;
    return &slot;
  }
  bool add(json&& v) {
    place(std::move(v));
    return true;
  }
  bool open(json&& empty) {
    const std::string at = next_path();
    levels_.push_back({place(std::move(empty)), at, {}});
    return true;
  }
  bool close() {
    levels_.pop_back();
    return true;
  }

  std::vector<Level> levels_;
};

// NaN, Infinity (as Python's json writes them) or a word in place of a number.
bool non_finite_literal(const std::string& text) {
  std::string word;
  for (char c : text) word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (word.starts_with('-') || word.starts_with('+')) word.erase(0, 1);
  return !word.empty() && (std::string_view("nan").starts_with(word) ||
                           std::string_view("infinity").starts_with(word));
}

// The literal that ends at `end` or contains the character before it.
std::pair<std::size_t, std::size_t> literal_around(std::string_view text, std::size_t end) {
  const auto part = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
  };
  std::size_t first = std::min(end, text.size());
  while (first > 0 && part(text[first - 1])) --first;
  std::size_t last = first;
  while (last < text.size() && part(text[last])) ++last;
  return {first, last};
}

nlohmann::json read_document(std::string_view text, const std::string& origin) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw ScenarioError(fmt::format("{}: the file is empty: a scenario is a JSON object", origin));
  }
  DocumentReader reader;
  nlohmann::json::sax_parse(text.begin(), text.end(), &reader);
  if (reader.error) {
    const DocumentReader::Error& e = *reader.error;
    const auto [first, last] = literal_around(text, e.position);
    const std::string literal(text.substr(first, last - first));
    const bool overflow = e.id == 406;
    // A number a double cannot hold, or NaN / Infinity: named at its key with
    // the element it is in (the text read again with that literal as 0).
    if (overflow || (e.id == 101 && non_finite_literal(literal))) {
      const std::string what =
          overflow
              ? fmt::format("{} is beyond the range of a double: not a finite number", literal)
              : fmt::format("{} is not a number in JSON, and numbers here must be finite", literal);
      std::string patched(text);
      patched.replace(first, last - first, "0");
      DocumentReader again;
      nlohmann::json::sax_parse(patched, &again);
      const nlohmann::json::json_pointer at(e.path);
      if (!again.error && again.document.contains(at)) {
        Node(again.document.at(at), origin, e.path, &again.document).fail(what);
      }
      throw ScenarioError(fmt::format("{}: {}: {}", origin, e.path.empty() ? "/" : e.path, what));
    }
    // e.what() reads "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    const auto at = e.what.find("] ");
    throw ScenarioError(fmt::format("{}: not JSON: {}{}", origin,
                                    at == std::string::npos ? e.what : e.what.substr(at + 2),
                                    e.path.empty() ? "" : fmt::format(" (in {})", e.path)));
  }
  if (reader.problem) {
    const auto& [path, what] = *reader.problem;
    Node(reader.document.at(nlohmann::json::json_pointer(path)), origin, path, &reader.document)
        .fail(what);
  }
  return std::move(reader.document);
}

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

// integrator: "name" | {"name", "tolerance", "rtol", "atol", "step", "global_tolerance"}
void read_integrator(const Node& root, Scenario& s) {
  const auto i = root.optional("integrator");
  if (!i) return;
  if (i->is_string()) {
    s.integrator = i->string();
    return;
  }
  i->allow_only({"name", "tolerance", "rtol", "atol", "step", "global_tolerance"});
  s.integrator = i->string_or("name", s.integrator);
  if (const auto t = i->optional("tolerance")) s.rtol = s.atol = t->positive();
  if (const auto t = i->optional("rtol")) s.rtol = t->positive();
  if (const auto t = i->optional("atol")) s.atol = t->positive();
  if (const auto t = i->optional("step")) s.step = t->positive();
  if (const auto t = i->optional("global_tolerance")) s.global_tolerance = t->positive();
}

void read_event_times(const Node& root, Scenario& s) {
  const auto events = root.optional("events");
  if (!events) return;
  for (const Node& e : events->elements()) {
    const Node t = e["time"];
    const double time = t.number();
    if (!(time > 0.0 && time < s.t_end))
      t.fail(fmt::format("expected a time inside (0, t_end = {}), found {}", s.t_end, time));
    s.event_times.push_back(time);
  }
  std::sort(s.event_times.begin(), s.event_times.end());
}

}  // namespace

Scenario parse_scenario(std::string_view text, std::string origin,
                        std::filesystem::path directory) {
  nlohmann::json document = read_document(text, origin);
  return scenario_from_document(std::move(document), std::move(origin), std::move(directory));
}

Scenario scenario_from_document(nlohmann::json document, std::string origin,
                                std::filesystem::path directory) {
  Scenario s;
  s.origin = std::move(origin);
  s.directory = std::move(directory);
  s.document = std::move(document);
  const Node root = s.root();
  root.allow_only({"$schema", "description", "model", "parameters", "initial", "variables",
                   "forces", "events", "integrator", "t_end", "output_interval", "outputs",
                   "checks", "shapes"});
  s.description = root.string_or("description", "");
  read_model(root, s);
  if (const auto t = root.optional("t_end")) s.t_end = t->positive();
  if (const auto t = root.optional("output_interval")) s.output_interval = t->positive();
  read_integrator(root, s);
  read_event_times(root, s);
  return s;
}

Scenario load_scenario(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw ScenarioError(
        fmt::format("scenario file '{}' is a directory: name a JSON file", file.string()));
  }
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
      scenario.root()["model"]["variant"].fail(fmt::format(
          "the module '{}' holds variant '{}', not '{}'", path.string(), m.variant(), wanted));
    }
    return m;
  }
  std::vector<std::string> variants, models;
  for (const auto& b : builtin_models()) {
    if (b.model != scenario.model) {
      if (std::find(models.begin(), models.end(), b.model) == models.end())
        models.push_back(b.model);
      continue;
    }
    if (wanted.empty() || b.variant == wanted) return b.make();
    variants.push_back(b.variant);
  }
  if (variants.empty()) {
    throw ScenarioError(
        fmt::format("{}: /model: no built-in model '{}' (built in: {}); a model of your own needs "
                    "\"module\"",
                    scenario.origin, scenario.model, fmt::join(models, ", ")));
  }
  throw ScenarioError(fmt::format("model '{}' has no variant '{}' (built variants: {})",
                                  scenario.model, wanted, fmt::join(variants, ", ")));
}

}  // namespace symdyn::sim
