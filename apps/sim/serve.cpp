#include "serve.hpp"

#include <fmt/format.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "overrides.hpp"
#include "run.hpp"
#include "scenario.hpp"

namespace symdyn::sim {

namespace {

using nlohmann::json;

// The shortest form that reads back exactly; NaN and the infinities as
// Python's json reads them.
void put_number(std::string& out, double v) {
  if (std::isnan(v)) {
    out += "NaN";
  } else if (std::isinf(v)) {
    out += v > 0.0 ? "Infinity" : "-Infinity";
  } else {
    fmt::format_to(std::back_inserter(out), "{}", v);
  }
}

void put_string(std::string& out, const std::string& text) {
  out += json(text).dump(-1, ' ', false, json::error_handler_t::replace);
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

constexpr const char* kCounters[] = {"steps",
                                     "rejected_steps",
                                     "rhs_evaluations",
                                     "residual_evaluations",
                                     "jacobian_evaluations",
                                     "newton_iterations"};

long counter(const runtime::Statistics& s, std::size_t k) {
  const long values[] = {s.steps,
                         s.rejected_steps,
                         s.rhs_evaluations,
                         s.residual_evaluations,
                         s.jacobian_evaluations,
                         s.newton_iterations};
  return values[k];
}

const json& member(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key)) {
    throw ScenarioError(fmt::format("request: missing member '{}'", key));
  }
  return object[key];
}

std::string text_member(const json& object, const char* key) {
  const json& v = member(object, key);
  if (!v.is_string()) throw ScenarioError(fmt::format("request: '{}' is not a string", key));
  return v.get<std::string>();
}

// One sweep as the engine runs it: the scenario, the paths each run changes,
// and the columns it keeps (docs/sweeps.md, "keep").
class Batch {
 public:
  explicit Batch(const json& load);

  std::string loaded() const;
  std::string run(const json& request) const;

 private:
  struct Column {
    enum class Source { value, check, counter } source;
    std::size_t index;  // into RunResult::values, the checks or kCounters
  };

  void read_keep(const Node& keep);
  void add_column(const std::string& name, Column column, const Node& at);
  void keep_expression(const std::string& name, const std::string& text, const Node& at);

  std::string origin_;  // the sweep file, for messages
  Scenario base_;
  runtime::Model model_;
  std::vector<std::string> paths_, ats_;
  json keep_;               // the sweep's "keep": kept_ points into it
  std::deque<json> texts_;  // expressions made from keep's shortcuts (stable addresses)
  std::vector<Node> kept_;  // Simulation::keep, in the order of the value columns
  std::vector<std::string> names_;
  std::vector<Column> columns_;
  bool series_ = false;
};

Scenario read_base(const json& scenario) {
  if (scenario.is_object() && scenario.contains("builtin"))
    return find_builtin(text_member(scenario, "builtin"));
  const std::string origin = text_member(scenario, "origin");
  Scenario s =
      parse_scenario(text_member(scenario, "text"), origin, text_member(scenario, "directory"));
  s.name = std::filesystem::path(origin).stem().string();
  return s;
}

Batch::Batch(const json& load)
    : origin_(text_member(load, "origin")),
      base_(read_base(member(load, "scenario"))),
      model_(make_model(base_)) {
  for (const json& t : member(load, "targets")) {
    paths_.push_back(text_member(t, "path"));
    ats_.push_back(text_member(t, "at"));
    try {
      check_override(base_, model_, paths_.back());
    } catch (const OverrideError& e) {
      throw ScenarioError(fmt::format("{}: {}: {}", origin_, ats_.back(), e.detail()));
    }
  }
  keep_ = load.contains("keep") ? load["keep"] : json::object();
  read_keep(
      Node(keep_, origin_, load.contains("keep_at") ? text_member(load, "keep_at") : "/keep"));
  // Every kept expression resolved against the scenario as it is, before any run.
  Simulation probe(base_);
  for (const Node& n : kept_) probe.keep(n);
}

void Batch::add_column(const std::string& name, Column column, const Node& at) {
  if (std::find(names_.begin(), names_.end(), name) != names_.end()) {
    at.fail(fmt::format("a second column named '{}'", name));
  }
  names_.push_back(name);
  columns_.push_back(column);
}

void Batch::keep_expression(const std::string& name, const std::string& text, const Node& at) {
  texts_.push_back(json(text));
  kept_.emplace_back(texts_.back(), origin_, at.path());
  add_column(name, {Column::Source::value, kept_.size() - 1}, at);
}

// {"final": true | ["q", "qd"], "values": {name: expression}, "extrema": [expression],
//  "at": {"times": [T], "of": [expression]}, "checks": true, "counters": false, "series": false}
void Batch::read_keep(const Node& keep) {
  keep.allow_only({"final", "values", "extrema", "at", "checks", "counters", "series"});
  bool q = true, qd = true;
  if (const auto f = keep.optional("final")) {
    if (f->json().is_boolean()) {
      q = qd = f->boolean();
    } else {
      q = qd = false;
      for (const Node& g : f->elements()) {
        const std::string group = g.string();
        if (group == "q") {
          q = true;
        } else if (group == "qd") {
          qd = true;
        } else {
          g.fail(fmt::format("unknown group '{}' (expected q or qd)", group));
        }
      }
    }
  }
  const Node final_at = keep.optional("final").value_or(keep);
  for (const std::string& name : model_.q_names()) {
    if (q) keep_expression(fmt::format("end({})", name), fmt::format("end({})", name), final_at);
  }
  for (const std::string& name : model_.q_names()) {
    if (qd)
      keep_expression(fmt::format("end({}_dot)", name), fmt::format("end({}_dot)", name), final_at);
  }
  if (const auto values = keep.optional("values")) {
    for (const auto& [name, value] : values->members()) {
      kept_.push_back(value);
      add_column(name, {Column::Source::value, kept_.size() - 1}, value);
    }
  }
  if (const auto extrema = keep.optional("extrema")) {
    for (const Node& e : extrema->elements()) {
      for (const char* f : {"minimum", "maximum"}) {
        const std::string text = fmt::format("{}({})", f, e.string());
        keep_expression(text, text, e);
      }
    }
  }
  if (const auto at = keep.optional("at")) {
    at->allow_only({"times", "of"});
    std::vector<double> times;
    for (const Node& t : (*at)["times"].elements()) times.push_back(t.number());
    for (const Node& e : (*at)["of"].elements()) {
      for (const double t : times) {
        const std::string text = fmt::format("at({}, {})", e.string(), t);
        keep_expression(text, text, e);
      }
    }
  }
  if (const auto c = keep.optional("checks"); !c || c->boolean()) {
    const auto checks = base_.root().optional("checks");
    const std::vector<Node> list = checks ? checks->elements() : std::vector<Node>{};
    for (std::size_t k = 0; k < list.size(); ++k) {
      add_column("check: " + list[k]["name"].string(), {Column::Source::check, k}, keep);
    }
  }
  if (const auto c = keep.optional("counters"); c && c->boolean()) {
    for (std::size_t k = 0; k < std::size(kCounters); ++k)
      add_column(kCounters[k], {Column::Source::counter, k}, *c);
  }
  if (const auto s = keep.optional("series")) series_ = s->boolean();
}

std::string Batch::loaded() const {
  std::string out = R"({"loaded": {"columns": [)";
  for (std::size_t k = 0; k < names_.size(); ++k) {
    if (k > 0) out += ", ";
    put_string(out, names_[k]);
  }
  out += "]}}";
  return out;
}

std::string Batch::run(const json& request) const {
  const double cpu0 = cpu_seconds();
  const auto wall0 = std::chrono::steady_clock::now();
  const json& index = member(request, "run");
  std::string status = "ok", error;
  std::vector<double> row(names_.size(), std::numeric_limits<double>::quiet_NaN());
  std::ostringstream csv;
  try {
    const json& values = member(request, "values");
    if (!values.is_array() || values.size() != paths_.size()) {
      throw ScenarioError(
          fmt::format("request: {} values expected, one per target", paths_.size()));
    }
    std::vector<Override> changes;
    for (std::size_t k = 0; k < paths_.size(); ++k) changes.push_back({paths_[k], values[k]});
    const Scenario scenario = with_overrides(base_, model_, changes);
    RunOptions options;
    if (series_) options.csv = &csv;
    Simulation simulation(scenario, options);
    for (const Node& n : kept_) simulation.keep(n);
    const RunResult r = simulation.run();
    std::vector<std::string> out_of_band;
    for (const Check& c : r.checks) {
      if (!c.ok()) {
        out_of_band.push_back(fmt::format("{} = {:.6g}{}, expected {:g} .. {:g}", c.name, c.value,
                                          c.unit.empty() ? "" : " " + c.unit, c.low, c.high));
      }
    }
    if (!out_of_band.empty()) {
      status = "out_of_band";
      error = fmt::format("out of band: {}", fmt::join(out_of_band, "; "));
    }
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      const Column& c = columns_[k];
      switch (c.source) {
        case Column::Source::value:
          row[k] = r.values[c.index];
          break;
        case Column::Source::check:
          row[k] = r.checks[c.index].value;
          break;
        case Column::Source::counter:
          row[k] = static_cast<double>(counter(r.statistics, c.index));
          break;
      }
    }
  } catch (const std::exception& e) {
    status = "failed";
    error = e.what();
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = cpu_seconds() - cpu0;

  std::string out = R"({"run": )";
  out += index.dump();
  out += R"(, "status": ")" + status + R"(", "error": )";
  put_string(out, error);
  out += R"(, "values": [)";
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (k > 0) out += ", ";
    put_number(out, row[k]);
  }
  out += R"(], "cpu": )";
  put_number(out, cpu);
  out += R"(, "wall": )";
  put_number(out, wall);
  if (series_) {
    out += R"(, "series": )";
    put_string(out, csv.str());
  }
  out += "}";
  return out;
}

std::string error_reply(const std::string& what) {
  std::string out = R"({"error": )";
  put_string(out, what);
  return out + "}";
}

}  // namespace

int serve(std::istream& in, std::ostream& out) {
  std::unique_ptr<Batch> batch;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const json request = json::parse(line, nullptr, /*allow_exceptions=*/false);
    std::string reply;
    try {
      if (request.is_discarded()) {
        reply = error_reply("request: not JSON");
      } else if (request.contains("load")) {
        batch.reset();
        batch = std::make_unique<Batch>(request["load"]);
        reply = batch->loaded();
      } else if (request.contains("run")) {
        reply = batch ? batch->run(request) : error_reply("request: no sweep loaded");
      } else if (request.contains("runs") && request["runs"].is_array() &&
                 !request["runs"].empty()) {
        // A row per run, written together: the driver wakes once per batch.
        if (!batch) {
          reply = error_reply("request: no sweep loaded");
        } else {
          for (const json& run : request["runs"]) {
            if (!reply.empty()) reply += '\n';
            reply += batch->run(run);
          }
        }
      } else {
        reply = error_reply("request: expected \"load\", \"run\" or \"runs\"");
      }
    } catch (const std::exception& e) {
      reply = error_reply(e.what());
    }
    out << reply << '\n' << std::flush;
  }
  return 0;
}

}  // namespace symdyn::sim
