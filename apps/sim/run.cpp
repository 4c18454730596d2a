#include "run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "elements.hpp"
#include <symdyn/runtime/breakpoints.hpp>
#include <symdyn/runtime/csv.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/progress_bar.hpp>

namespace symdyn::sim {

using runtime::MultibodySystem;
using runtime::State;
using runtime::Vector;

namespace {

// A statistic of a quantity over the output instants, updated as they come:
// start(e), end(e), maximum(e), minimum(e), drift(e) = max |e - e(0)|,
// max_rise(e) = max of e(t_k) - e(t_k-1) (0 if it never rises), at(e, T) = e
// at the first output instant t >= T.
struct Statistic {
  enum class Kind { start, end, maximum, minimum, drift, max_rise, at } kind;
  Expression of;
  double time = 0.0;  // at()
  double value = std::numeric_limits<double>::quiet_NaN();
  double first = 0.0, previous = 0.0;
  bool seen = false;

  void update(double t, double v) {
    switch (kind) {
      case Kind::start:
        if (!seen) value = v;
        break;
      case Kind::end:
        value = v;
        break;
      case Kind::maximum:
        value = seen ? std::max(value, v) : v;
        break;
      case Kind::minimum:
        value = seen ? std::min(value, v) : v;
        break;
      case Kind::drift:
        if (!seen) first = v, value = 0.0;
        value = std::max(value, std::abs(v - first));
        break;
      case Kind::max_rise:
        value = seen ? std::max(value, v - previous) : 0.0;
        break;
      case Kind::at:
        if (std::isnan(value) && t >= time - 1e-9 * std::max(1.0, std::abs(time))) value = v;
        break;
    }
    previous = v;
    seen = true;
  }
};

constexpr std::pair<const char*, Statistic::Kind> kStatistics[] = {
    {"start", Statistic::Kind::start},     {"end", Statistic::Kind::end},
    {"maximum", Statistic::Kind::maximum}, {"minimum", Statistic::Kind::minimum},
    {"drift", Statistic::Kind::drift},     {"max_rise", Statistic::Kind::max_rise},
    {"at", Statistic::Kind::at},
};

struct CheckSpec {
  std::string name, unit;
  Expression value, low, high;
};

// The changes an event makes at its time.
struct Event {
  double time = 0.0;
  std::vector<std::pair<ScenarioElement*, bool>> switches;
  std::vector<std::pair<std::size_t, double>> variables;
  std::vector<std::pair<std::string, double>> parameters;
};

// The values of the run's constants (rtol, atol, t_end), for what is known before the run.
class RunConstants : public Environment {
 public:
  explicit RunConstants(const SymbolTable& table) : table_(table) {}
  double value(int s) const override { return table_[s].constant; }

 private:
  const SymbolTable& table_;
};

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

}  // namespace

struct Simulation::Impl {
  const Scenario& scenario;
  RunOptions options;
  std::unique_ptr<MultibodySystem> system;
  std::vector<std::shared_ptr<ScenarioElement>> elements;
  std::vector<double> variables;
  Names names;
  SymbolTable table;
  std::vector<Statistic> statistics;
  std::vector<double> statistic_values;
  std::vector<CheckSpec> checks;
  std::vector<Expression> kept;  // Simulation::keep
  std::vector<std::pair<std::string, Expression>> channels;
  std::vector<Node> channel_nodes;  // where each channel was asked for
  runtime::CsvRecorder::Columns groups;
  std::vector<Event> events;
  State initial;
  std::string integrator;
  runtime::IntegratorOptions integrator_options;
  double t_end = 0.0;
  RunResult result;

  Impl(const Scenario& s, const RunOptions& o) : scenario(s), options(o) {}

  Node root() const { return scenario.root(); }

  void build() {
    runtime::Model model = make_model(scenario, options.variant);
    read_parameters(model);
    const bool emitted = !options.assembled && model.has_equations_of_motion();
    result.equations = emitted ? "emitted" : "assembled";
    system = std::make_unique<MultibodySystem>(
        std::move(model),
        emitted ? runtime::EquationsSource::emitted : runtime::EquationsSource::assembled);
    names.model = &system->model();
    names.elements = &elements;
    read_times();
    read_variables();
    read_forces();
    read_initial_state();
    read_events();
    read_outputs();
    read_checks();
  }

  void read_parameters(runtime::Model& model) {
    const auto p = root().optional("parameters");
    if (!p) return;
    for (const auto& [name, value] : p->members()) {
      const auto& valid = model.param_names();
      if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
        value.fail(fmt::format("unknown parameter '{}' ({})", name,
                               valid.empty()
                                   ? "the model has no run-time parameters"
                                   : fmt::format("parameters: {}", fmt::join(valid, ", "))));
      }
      try {
        model.set_parameter(name, value.number());
      } catch (const runtime::ModelError& e) {
        value.fail(e.what());
      }
    }
  }

  void read_times() {
    t_end = options.t_end.value_or(scenario.t_end);
    result.t_end = t_end;
    integrator = options.integrator.empty() ? scenario.integrator : options.integrator;
    auto& o = integrator_options;
    const std::optional<double> tolerance = options.tolerance;
    o.relative_tolerance = options.rtol.value_or(tolerance.value_or(scenario.rtol));
    o.absolute_tolerance = options.atol.value_or(tolerance.value_or(scenario.atol));
    o.output_interval = options.output_interval.value_or(scenario.output_interval);
    o.global_tolerance = options.global_tolerance.value_or(scenario.global_tolerance.value_or(0.0));
    if (options.step || scenario.step) {
      o.initial_step = options.step.value_or(scenario.step.value_or(0.0));
    } else if (integrator == "rk4" || integrator == "midpoint") {
      throw runtime::OptionError(fmt::format(
          "integrator '{}' takes a fixed step: give one (--step, or the scenario's integrator "
          "\"step\"){}",
          integrator,
          o.global_tolerance > 0.0 ? "; with a global tolerance it is the first of the halved steps"
                                   : ""));
    }
    names.rtol = o.relative_tolerance;
    names.atol = o.absolute_tolerance;
    names.t_end = t_end;
    runtime::make_integrator(integrator);  // an unknown name: OptionError listing the valid ones
  }

  void read_variables() {
    const auto v = root().optional("variables");
    if (!v) return;
    const auto& q = system->model().q_names();
    for (const auto& [name, value] : v->members()) {
      if (!is_identifier(name) || name == "t" || name == "pi" ||
          std::find(q.begin(), q.end(), name) != q.end()) {
        value.fail(fmt::format(
            "'{}' cannot name a variable (letters, digits and _, not t, pi or a coordinate)",
            name));
      }
      const auto& bodies = system->model().body_names();
      if (name == "ground" || std::find(bodies.begin(), bodies.end(), name) != bodies.end()) {
        value.fail(fmt::format("'{}' is a body's name: name the variable otherwise", name));
      }
      names.variables.push_back(name);
      variables.push_back(value.number());
    }
  }

  void read_forces() {
    const auto f = root().optional("forces");
    if (!f) return;
    const ElementContext context{names, table, variables};
    const auto& bodies = system->model().body_names();
    for (const Node& node : f->elements()) {
      auto e = make_element(node, context);
      const Node id = node["name"];
      for (const auto& other : elements) {
        if (other->id() == e->id())
          id.fail(fmt::format("a second force element named '{}'", e->id()));
      }
      if (std::find(bodies.begin(), bodies.end(), e->id()) != bodies.end()) {
        id.fail(fmt::format("'{}' is a body's name: name the element otherwise", e->id()));
      }
      if (std::find(names.variables.begin(), names.variables.end(), e->id()) !=
          names.variables.end()) {
        id.fail(fmt::format("'{}' is a variable's name: name the element otherwise", e->id()));
      }
      elements.push_back(e);
      system->add(e);
    }
  }

  // By coordinate name: {"q": {"q0": 0.1}, "qd": {...}}; the rest as the model's.
  // With closed loops, an implicit dependent parameter's q is the guess its
  // first solve starts from (the assembly branch); its rate follows from qd.
  void read_initial_state() {
    initial = system->initial_state();
    const auto init = root().optional("initial");
    if (!init) return;
    init->allow_only({"q", "qd"});
    const runtime::Model& model = system->model();
    const auto& q = model.q_names();
    runtime::Vector guess = model.initial_state().q.tail(model.ncon());
    for (const auto& [key, into] : {std::pair{"q", &initial.q}, {"qd", &initial.qd}}) {
      const auto values = init->optional(key);
      if (!values) continue;
      for (const auto& [name, value] : values->members()) {
        const auto it = std::find(q.begin(), q.end(), name);
        if (it == q.end())
          value.fail(
              fmt::format("unknown coordinate '{}' (coordinates: {})", name, fmt::join(q, ", ")));
        const auto j = it - q.begin();
        if (j < into->size()) {
          (*into)(j) = value.number();
        } else if (into == &initial.q) {
          guess(j - into->size()) = value.number();
        } else {
          value.fail(fmt::format(
              "'{}' is an implicit dependent parameter of the closed loops ({}): its rate follows "
              "from the independent coordinates' ({})",
              name, fmt::join(model.loop_names(), ", "),
              fmt::join(std::vector<std::string>(q.begin(), q.begin() + into->size()), ", ")));
        }
      }
    }
    if (model.has_loops()) system->set_loop_guess(guess);
  }

  ScenarioElement* element(const Node& n) const {
    const std::string name = n.string();
    std::vector<std::string> ids;
    for (const auto& e : elements) {
      if (e->id() == name) return e.get();
      ids.push_back(e->id());
    }
    n.fail(fmt::format("unknown force element '{}' (elements: {})", name,
                       ids.empty() ? "none" : fmt::format("{}", fmt::join(ids, ", "))));
  }

  // {"time", "enable": name | [names], "disable": ..., "set": {variable: value}, "parameters":
  // {name: value}}
  void read_events() {
    const auto list = root().optional("events");
    if (!list) return;
    std::map<double, Event> by_time;
    for (const Node& node : list->elements()) {
      node.allow_only({"time", "enable", "disable", "set", "parameters"});
      const double time = node["time"].number();  // inside (0, t_end): checked when loaded
      Event& e = by_time[time];
      e.time = time;
      for (const auto& [key, on] : {std::pair{"enable", true}, {"disable", false}}) {
        const auto n = node.optional(key);
        if (!n) continue;
        if (n->is_string()) {
          e.switches.emplace_back(element(*n), on);
        } else {
          for (const Node& m : n->elements()) e.switches.emplace_back(element(m), on);
        }
      }
      if (const auto set = node.optional("set")) {
        for (const auto& [name, value] : set->members()) {
          const auto it = std::find(names.variables.begin(), names.variables.end(), name);
          if (it == names.variables.end()) {
            value.fail(fmt::format("unknown variable '{}' (variables: {})", name,
                                   names.variables.empty()
                                       ? "none"
                                       : fmt::format("{}", fmt::join(names.variables, ", "))));
          }
          e.variables.emplace_back(static_cast<std::size_t>(it - names.variables.begin()),
                                   value.number());
        }
      }
      if (const auto p = node.optional("parameters")) {
        const auto& valid = system->model().param_names();
        for (const auto& [name, value] : p->members()) {
          if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
            value.fail(
                fmt::format("unknown parameter '{}' (parameters: {})", name,
                            valid.empty() ? "none" : fmt::format("{}", fmt::join(valid, ", "))));
          }
          e.parameters.emplace_back(name, value.number());
        }
      }
    }
    for (auto& [time, e] : by_time) {
      if (time < t_end) events.push_back(std::move(e));  // a shorter --t-end drops the later ones
    }
  }

  void apply(const Event& e) {
    for (const auto& [element, on] : e.switches) element->enable(on);
    for (const auto& [v, value] : e.variables) variables[v] = value;
    for (const auto& [name, value] : e.parameters) system->set_parameter(name, value);
  }

  Scope sample_scope() const {
    return {.time = true, .state = true, .accelerations = true, .system = true};
  }

  void add_channel(std::string name, const std::string& text, const Node& at) {
    Expression e;
    try {
      e = Expression::parse(text, make_resolver(names, sample_scope(), table));
    } catch (const ExpressionError& x) {
      at.fail(x.what());
    }
    channels.emplace_back(std::move(name), std::move(e));
    channel_nodes.push_back(at);
  }

  // Two columns of one name would make the CSV ambiguous: an output named
  // like a coordinate ("q0"), "t", or another output.
  void check_columns() const {
    std::ostringstream unused;
    runtime::CsvRecorder probe(unused, *system, groups);
    for (const auto& [name, e] : channels)
      probe.add_channel(name, [](const State&) { return 0.0; });
    const std::vector<std::string> columns = probe.columns();
    const std::size_t first = columns.size() - channels.size();
    for (std::size_t k = 0; k < channels.size(); ++k) {
      const auto end = columns.begin() + static_cast<std::ptrdiff_t>(first + k);
      if (std::find(columns.begin(), end, channels[k].first) != end) {
        channel_nodes[k].fail(fmt::format(
            "the CSV already has a column '{}': name this output otherwise", channels[k].first));
      }
    }
  }

  // "q", "qd", "qdd", "energies"; {"body", "quantity"}; {"element", "quantity"}; {"name", "value"}.
  void read_outputs() {
    const auto list = root().optional("outputs");
    if (!list) {  // the default groups: q, qd, energies
      add_dependent_channels(root());
      return;
    }
    groups = {.coordinates = false,
              .rates = false,
              .accelerations = false,
              .extra_states = true,
              .energies = false};
    for (const Node& n : list->elements()) {
      if (n.is_string()) {
        const std::string g = n.string();
        if (g == "q") {
          groups.coordinates = true;
        } else if (g == "qd") {
          groups.rates = true;
        } else if (g == "qdd") {
          groups.accelerations = true;
        } else if (g == "energies") {
          groups.energies = true;
        } else {
          n.fail(
              fmt::format("unknown output '{}' (expected q, qd, qdd, energies, or an object)", g));
        }
      } else if (n.has("body")) {
        read_body_output(n);
      } else if (n.has("element")) {
        read_element_output(n);
      } else if (n.has("loop")) {
        read_loop_output(n);
      } else {
        n.allow_only({"name", "value"});
        const Node value = n["value"];
        add_channel(n["name"].string(),
                    value.is_number() ? fmt::format("{}", value.number()) : value.string(), value);
      }
    }
    add_dependent_channels(*list);
    check_columns();
  }

  // Closed loops: the groups q, qd, qdd hold the independent coordinates (the
  // state); the implicit dependent parameters p follow them by name.
  void add_dependent_channels(const Node& at) {
    const runtime::Model& model = system->model();
    for (int j = model.nindependent(); j < model.nq(); ++j) {
      const std::string& p = model.q_names()[static_cast<std::size_t>(j)];
      if (groups.coordinates) add_channel(p, p, at);
      if (groups.rates) add_channel(p + "_dot", p + "_dot", at);
      if (groups.accelerations) add_channel(p + "_ddot", p + "_ddot", at);
    }
  }

  // {"loop": name}: its reactions, reaction.<loop>.Fx .. (docs/scenarios.md).
  void read_loop_output(const Node& n) {
    n.allow_only({"loop"});
    const runtime::Model& model = system->model();
    const std::string loop = n["loop"].string();
    const auto& loops = model.loop_names();
    if (std::find(loops.begin(), loops.end(), loop) == loops.end()) {
      n["loop"].fail(
          fmt::format("unknown loop '{}' (loops: {})", loop,
                      loops.empty() ? "none" : fmt::format("{}", fmt::join(loops, ", "))));
    }
    for (int k = 0; k < model.ncon(); ++k) {
      if (loops[static_cast<std::size_t>(model.constraint_loop(k))] != loop) continue;
      const std::string column = "reaction." + model.loop_reaction_name(k);
      add_channel(column, column, n["loop"]);
    }
  }

  void read_body_output(const Node& n) {
    n.allow_only({"body", "quantity"});
    const std::string body = n["body"].string();
    const auto& bodies = system->model().body_names();
    if (std::find(bodies.begin(), bodies.end(), body) == bodies.end()) {
      n["body"].fail(fmt::format("unknown body '{}' (bodies: {})", body, fmt::join(bodies, ", ")));
    }
    const std::pair<const char*, std::vector<const char*>> kinds[] = {
        {"position", {"x", "y", "z"}},
        {"velocity", {"vx", "vy", "vz"}},
        {"angular_velocity", {"wx", "wy", "wz"}},
        {"velocity_local", {"ux", "uy", "uz"}},
        {"orientation", {"R00", "R01", "R02", "R10", "R11", "R12", "R20", "R21", "R22"}},
    };
    const Node q = n["quantity"];
    const std::string kind = q.string();
    if (kind == "reaction") {  // reaction.<body>.Fx ..: not an attribute of the body
      for (const char* c : runtime::Model::kReactionComponents) {
        const std::string column = fmt::format("reaction.{}.{}", body, c);
        add_channel(column, column, q);
      }
      return;
    }
    for (const auto& [name, attributes] : kinds) {
      if (kind != name) continue;
      for (const char* a : attributes) add_channel(body + "." + a, body + "." + a, q);
      return;
    }
    q.fail(
        fmt::format("unknown body quantity '{}' (expected position, velocity, angular_velocity, "
                    "velocity_local, orientation, reaction)",
                    kind));
  }

  void read_element_output(const Node& n) {
    n.allow_only({"element", "quantity"});
    const ScenarioElement* e = element(n["element"]);
    if (!n.has("quantity")) {
      for (const auto& q : e->quantity_names())
        add_channel(e->id() + "." + q, e->id() + "." + q, n["element"]);
      return;
    }
    const Node q = n["quantity"];
    const auto& valid = e->quantity_names();
    if (std::find(valid.begin(), valid.end(), q.string()) == valid.end()) {
      q.fail(fmt::format("unknown quantity '{}' of force element '{}' (quantities: {})", q.string(),
                         e->id(), fmt::join(valid, ", ")));
    }
    add_channel(e->id() + "." + q.string(), e->id() + "." + q.string(), q);
  }

  // Statistic calls become symbols whose values the accumulators keep.
  Resolver check_resolver() {
    Resolver r =
        make_resolver(names, {.time = false, .state = false, .run_constants = true}, table);
    // A quantity that varies during the run, read outside a statistic: say how to read it.
    r.symbol = [this, constants = r.symbol](std::string_view name) {
      try {
        return constants(name);
      } catch (const ExpressionError&) {
        SymbolTable scratch;
        resolve_name(name, names, sample_scope(),
                     scratch);  // unknown anywhere: says so, listing the names
        throw ExpressionError(
            fmt::format("'{}' varies during the run: a check reads it through start(), end(), "
                        "maximum(), minimum(), drift(), max_rise() or at()",
                        name));
      }
    };
    r.call = [this](std::string_view function, const std::vector<std::string_view>& args) -> int {
      const auto row = std::find_if(std::begin(kStatistics), std::end(kStatistics),
                                    [&](const auto& s) { return function == s.first; });
      if (row == std::end(kStatistics)) {
        throw ExpressionError(
            fmt::format("unknown function '{}' (statistics: start, end, maximum, minimum, drift, "
                        "max_rise, at; and the functions of expressions)",
                        function));
      }
      const std::size_t arity = row->second == Statistic::Kind::at ? 2 : 1;
      if (args.size() != arity) {
        throw ExpressionError(fmt::format("{}() takes {} argument{}, given {}", function, arity,
                                          arity == 1 ? "" : "s", args.size()));
      }
      Statistic s{.kind = row->second,
                  .of = Expression::parse(args[0], make_resolver(names, sample_scope(), table))};
      if (arity == 2) {  // the time: a number, or of rtol, atol, t_end
        const RunConstants constants(table);
        s.time =
            Expression::parse(
                args[1],
                make_resolver(names, {.time = false, .state = false, .run_constants = true}, table))
                .evaluate(constants);
        // Outside the run, at() would never be set: its check would read NaN.
        if (!(s.time >= 0.0 && s.time <= t_end)) {
          throw ExpressionError(fmt::format(
              "at(): the time {:.6g} is outside the run [0, t_end = {:.6g}]", s.time, t_end));
        }
      }
      statistics.push_back(std::move(s));
      return table.add({.source = Source::statistic, .a = static_cast<int>(statistics.size() - 1)});
    };
    return r;
  }

  // A band whose ends read no statistic is known now: refused before the run
  // when reversed (no value could pass) or not finite.
  void check_band(const CheckSpec& c, const Node& band) const {
    const auto known = [&](const Expression& e) {
      return std::none_of(e.symbols().begin(), e.symbols().end(),
                          [&](int s) { return table[s].source == Source::statistic; });
    };
    if (!known(c.low) || !known(c.high)) return;
    const RunConstants constants(table);
    const double low = c.low.evaluate(constants), high = c.high.evaluate(constants);
    if (!std::isfinite(low) || !std::isfinite(high)) {
      band.fail(fmt::format("the band [{:.6g}, {:.6g}] is not finite", low, high));
    }
    if (low > high) {
      band.fail(fmt::format(
          "the band [{:.6g}, {:.6g}] is reversed: its low end is above its high end, so no value "
          "passes; write [{:.6g}, {:.6g}]",
          low, high, high, low));
    }
  }

  void read_checks() {
    const auto list = root().optional("checks");
    if (!list) return;
    const Resolver resolver = check_resolver();
    for (const Node& n : list->elements()) {
      n.allow_only({"name", "value", "unit", "band"});
      CheckSpec c{.name = n["name"].string(),
                  .unit = n.string_or("unit", ""),
                  .value = {},
                  .low = {},
                  .high = {}};
      c.value = read_expression(n["value"], resolver);
      const Node band = n["band"];
      const auto ends = band.elements();
      if (ends.size() != 2)
        band.fail(fmt::format("expected [low, high], found {} entries", ends.size()));
      c.low = read_expression(ends[0], resolver);
      c.high = read_expression(ends[1], resolver);
      check_band(c, band);
      checks.push_back(std::move(c));
    }
    statistic_values.assign(statistics.size(), 0.0);
  }

  double expected_rows() const {
    return t_end / integrator_options.output_interval + static_cast<double>(events.size());
  }

  RunResult run();
};

RunResult Simulation::Impl::run() {
  RunResult& r = result;
  r.model = system->model().name();
  r.variant = system->model().variant();
  r.integrator = integrator;
  r.relative_tolerance = integrator_options.relative_tolerance;
  r.absolute_tolerance = integrator_options.absolute_tolerance;
  r.global_tolerance = integrator_options.global_tolerance;

  std::ostringstream unused;
  runtime::CsvRecorder csv(options.csv != nullptr ? *options.csv : unused, *system, groups);
  SampleEnvironment env(*system, table, elements, variables, statistic_values);
  for (const auto& [name, e] : channels) {
    csv.add_channel(name, [&env, &e = e](const State&) { return e.evaluate(env); });
  }
  r.columns = csv.columns();
  r.coordinates = system->model().q_names();

  bool first = true;
  auto o = integrator_options;
  o.on_output = [&](const State& s, const Vector& qdd, const Vector&) {
    env.set(s, qdd);
    const runtime::Energies e = system->energies(s);
    env.set(s, qdd);  // energies() evaluated the kinematics: read again when asked
    if (first) {
      r.initial = s;
      r.energy.initial = e.total();
      r.energy.scale = std::abs(e.total());
      first = false;
    }
    r.final = s;
    r.energy.final = e.total();
    r.energy.absolute = std::max(r.energy.absolute, std::abs(e.total() - r.energy.initial));
    r.energy.scale = std::max(r.energy.scale, e.kinetic);
    for (auto& st : statistics) st.update(s.t, st.of.evaluate(env));
    ++r.rows;
    if (options.on_sample) options.on_sample(s, qdd);
    if (options.csv != nullptr) csv.write(s, qdd);
  };
  runtime::ProgressBar bar;
  if (options.progress) o.on_progress = bar.callback();
  auto integ = runtime::make_integrator(integrator, o);

  std::vector<double> breakpoints;
  for (const auto& e : events) breakpoints.push_back(e.time);
  system->clear_warnings();
  const auto start = std::chrono::steady_clock::now();
  const runtime::SegmentedRun run =
      runtime::integrate_with_breakpoints(*integ, *system, initial, breakpoints, t_end,
                                          [&](std::size_t k, State&) { apply(events[k]); });
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bar.finish();
  r.statistics = run.statistics;
  r.segments = run.segments;
  r.warnings = system->warnings();
  r.jacobians = system->jacobian_method();

  for (std::size_t k = 0; k < statistics.size(); ++k) statistic_values[k] = statistics[k].value;
  for (const auto& c : checks) {
    r.checks.push_back(
        {c.name, c.value.evaluate(env), c.unit, c.low.evaluate(env), c.high.evaluate(env)});
  }
  for (const Expression& e : kept) r.values.push_back(e.evaluate(env));
  return r;
}

Simulation::Simulation(const Scenario& scenario, const RunOptions& options)
    : impl_(std::make_unique<Impl>(scenario, options)) {
  impl_->build();
}

Simulation::~Simulation() = default;

double Simulation::expected_rows() const {
  return impl_->expected_rows();
}

runtime::MultibodySystem& Simulation::system() {
  return *impl_->system;
}

void Simulation::keep(const Node& value) {
  impl_->kept.push_back(read_expression(value, impl_->check_resolver()));
  impl_->statistic_values.resize(impl_->statistics.size(), 0.0);
}

RunResult Simulation::run() {
  return impl_->run();
}

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  Simulation sim(scenario, options);
  return sim.run();
}

std::string summary(const RunResult& run) {
  const auto& st = run.statistics;
  const std::string tolerance =
      run.relative_tolerance == run.absolute_tolerance
          ? fmt::format("tolerance {:g}", run.relative_tolerance)
          : fmt::format("rtol {:g}, atol {:g}", run.relative_tolerance, run.absolute_tolerance);
  std::string out =
      fmt::format("{} ({}, {} equations), {} at {}, t = 0 .. {:g} s{}\n", run.model, run.variant,
                  run.equations, run.integrator, tolerance, run.t_end,
                  run.segments > 1 ? fmt::format(" in {} segments", run.segments) : "");
  out += fmt::format(
      "  steps {} (rejected {}), evaluations: {} accelerations, {} residuals, {} Jacobians; {:.3f} "
      "s\n",
      st.steps, st.rejected_steps, st.rhs_evaluations, st.residual_evaluations,
      st.jacobian_evaluations, run.wall_seconds);
  if (st.jacobian_evaluations > 0) out += fmt::format("  Jacobians: {}\n", run.jacobians);
  if (run.global_tolerance > 0.0) {
    const std::string last =
        st.extrapolated
            ? fmt::format("steps {:g} and {:g} s, extrapolated", 2 * st.last_step, st.last_step)
        : st.last_step > 0.0 ? fmt::format("step {:g} s", st.last_step)
                             : fmt::format("tolerance {:g}", st.last_relative_tolerance);
    out += fmt::format(
        "  global error: estimated {:.3g}, global tolerance {:g} {} ({} runs, the result's at "
        "{})\n",
        st.global_error_estimate, run.global_tolerance, st.global_tolerance_met ? "met" : "NOT MET",
        st.runs, last);
  } else {
    out +=
        "  global error: not estimated (the tolerance bounds each step's error; --global-tolerance "
        "estimates it)\n";
  }
  const State& s = run.final;
  std::string q, qd;
  for (Eigen::Index j = 0; j < s.q.size(); ++j) {
    const auto& name = run.coordinates[static_cast<std::size_t>(j)];
    q += fmt::format("{}{} = {:.6f}", j ? ", " : "", name, s.q(j));
    qd += fmt::format("{}{}_dot = {:.6f}", j ? ", " : "", name, s.qd(j));
  }
  out += fmt::format("  final state at t = {:g}: {}\n                        {}\n", s.t, q, qd);
  out += fmt::format(
      "  energy: initial {:.9g} J, final {:.9g} J, max |E - E0| = {:.3g} J ({:.3g} of {:.4g} J)\n",
      run.energy.initial, run.energy.final, run.energy.absolute, run.energy.relative(),
      run.energy.scale);
  for (const auto& w : run.warnings) out += fmt::format("  WARNING: {}\n", w);
  for (const auto& c : run.checks) {
    out += fmt::format("  {}: {:.6g}{} (expected {:g} .. {:g}) {}\n", c.name, c.value,
                       c.unit.empty() ? "" : " " + c.unit, c.low, c.high,
                       c.ok() ? "ok" : "OUT OF RANGE");
  }
  return out;
}

}  // namespace symdyn::sim
