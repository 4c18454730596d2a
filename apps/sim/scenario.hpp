#pragma once
// Scenario files (docs/scenarios.md, docs/scenario.schema.json): what
// symdyn-sim runs, as data. A scenario names a model (built in, or a model
// module next to the file), its parameters and initial state, force elements,
// events, the integrator, outputs and checks. Loading reads the document and
// the fields needed before the model exists (model, integrator, times);
// Simulation (run.hpp) resolves every name against the model. Every error is
// a ScenarioError naming the file, the JSON path of the culprit and what was
// expected:
//   double_pendulum.json: /forces/0/body (force element 'strut'): unknown body 'rod3' (bodies:
//   rod1, rod2)

#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/model.hpp>

namespace symdyn::sim {

// A bad scenario: the run is refused before any file is touched (exit 2).
class ScenarioError : public runtime::OptionError {
 public:
  using runtime::OptionError::OptionError;
};

// A value of the document with its JSON path, so that every message names
// the culprit. Accessors check the type and throw ScenarioError.
class Node {
 public:
  // `root`: the document `value` is in (itself when omitted), to name the
  // force element or check a path is inside.
  Node(const nlohmann::json& value, std::string origin, std::string path = "",
       const nlohmann::json* root = nullptr)
      : value_(&value),
        root_(root != nullptr ? root : &value),
        origin_(std::move(origin)),
        path_(std::move(path)) {}

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }
  // "swing.json: /forces/1/stiffness (force element 'strut')"
  std::string where() const;
  [[noreturn]] void fail(const std::string& what) const;

  // Object members: the keys allowed here (others are refused, listing these).
  void allow_only(std::initializer_list<std::string_view> keys) const;
  bool has(std::string_view key) const;
  Node operator[](std::string_view key) const;  // required member
  std::optional<Node> optional(std::string_view key) const;
  std::vector<std::pair<std::string, Node>> members() const;  // of an object, sorted by key
  std::vector<Node> elements() const;                         // of an array

  bool is_string() const { return value_->is_string(); }
  bool is_number() const { return value_->is_number(); }
  bool is_object() const { return value_->is_object(); }
  std::string string() const;
  double number() const;    // finite
  double positive() const;  // finite and > 0
  bool boolean() const;
  std::vector<double> numbers(std::size_t n) const;  // an array of n finite numbers

  // Member shortcuts with a default when absent.
  double number_or(std::string_view key, double fallback) const;
  std::string string_or(std::string_view key, std::string fallback) const;

 private:
  Node child(const nlohmann::json& value, const std::string& segment) const {
    return Node(value, origin_, path_ + "/" + segment, root_);
  }

  const nlohmann::json* value_;
  const nlohmann::json* root_;
  std::string origin_;
  std::string path_;
};

struct Scenario {
  std::string name;                 // the file's stem, or the built-in model's name
  std::string origin;               // the file, for messages
  std::filesystem::path directory;  // a module path is relative to it
  nlohmann::json document;

  // Read when loaded (the rest is read by Simulation, against the model).
  std::string description;
  std::string model;    // the model's name (a module's must match it, if given)
  std::string variant;  // empty: a built-in model's first built variant
  std::string module;   // the module's path as written, empty for a built-in model
  double t_end = 1.0;
  double output_interval = 0.01;
  std::string integrator = "dopri5";
  double rtol = 1e-8, atol = 1e-8;
  std::optional<double> step;
  std::optional<double> global_tolerance;
  std::vector<double> event_times;  // sorted, for the row estimate

  Node root() const { return Node(document, origin); }
};

// Throws ScenarioError (unreadable file, not JSON, a key given twice in an
// object, a number a double cannot hold, bad structure).
Scenario load_scenario(const std::filesystem::path& file);
Scenario parse_scenario(std::string_view text, std::string origin,
                        std::filesystem::path directory = {});
// The same from a document already read (a scenario changed by overrides.hpp).
Scenario scenario_from_document(nlohmann::json document, std::string origin,
                                std::filesystem::path directory = {});

// The reference models built into symdyn-sim, each generated variant a factory.
struct BuiltinModel {
  std::string model, variant;
  runtime::Model (*make)();
};
const std::vector<BuiltinModel>& builtin_models();

// The scenarios of models/scenarios/*.json whose model has a built variant,
// sorted by name; find_builtin throws ScenarioError naming the known ones.
const std::vector<Scenario>& builtin_scenarios();
const Scenario& find_builtin(std::string_view name);

// The model a scenario names: a module (relative to the scenario's
// directory) or a built-in model; `variant` overrides the scenario's.
runtime::Model make_model(const Scenario& scenario, std::string_view variant = {});

}  // namespace symdyn::sim
