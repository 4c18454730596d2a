#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include <symdyn/detail/inertia.hpp>
#include <symdyn/model/identifier.hpp>
#include <symdyn/model/model.hpp>
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/simplify.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model {

using symbolic::SymbolKind;

namespace {

// Names of the derivatives of a symbol: q3 -> qd3, qdd3; yaw -> yaw_d, yaw_dd.
std::pair<std::string, std::string> derivative_names(std::string_view name) {
  const bool q_style =
      name.size() > 1 && name[0] == 'q' &&
      std::all_of(name.begin() + 1, name.end(), [](char c) { return std::isdigit(c) != 0; });
  if (q_style) return {fmt::format("qd{}", name.substr(1)), fmt::format("qdd{}", name.substr(1))};
  return {fmt::format("{}_d", name), fmt::format("{}_dd", name)};
}

// Declares a symbol; a name taken by a symbol of another kind is a model error.
Expr declare(std::string_view name, SymbolKind kind) {
  try {
    return symbolic::symbol(name, kind);
  } catch (const symbolic::UsageError& e) {
    throw ModelError(e.what());
  }
}

void check_builder_name(std::string_view name, std::string_view what) {
  check_name(name, fmt::format("{} name", what));
}

// "coordinate 'q0'", "time 't'", ...: a symbol as a message names it.
std::string describe_symbol(Expr s) {
  switch (s.symbol_kind()) {
    case SymbolKind::Variable:
      return fmt::format("coordinate '{}'", s.name());  // or implicit dependent parameter
    case SymbolKind::Time:
      return fmt::format("time '{}'", s.name());
    case SymbolKind::Parameter:
      return fmt::format("run-time parameter '{}'", s.name());
    case SymbolKind::Dependent:
      return fmt::format("dependent parameter '{}'", s.name());
    default:
      return fmt::format("rate or acceleration '{}'", s.name());
  }
}

// The first symbol of `e` that is not a run-time parameter: a mass or an
// inertia is emitted in inertia(param), which sees no q, t or p.
std::optional<Expr> non_constant_symbol(Expr e) {
  if (e.is_number()) return std::nullopt;
  for (Expr s : symbolic::free_symbols(std::span<const Expr>(&e, 1))) {
    if (s.symbol_kind() != SymbolKind::Parameter) return s;
  }
  return std::nullopt;
}

// The innermost operation of `e` whose value is not finite, as a user wrote it
// ("asin(2.5)", "sqrt(-1)", "pow(0, -1)"), or nothing when `e` is finite.
std::optional<std::string> undefined_operation(Expr e, symbolic::Evaluator<double>& evaluate) {
  if (std::isfinite(evaluate(e))) return std::nullopt;
  for (Expr node : symbolic::postorder(std::span<const Expr>(&e, 1))) {
    if (std::isfinite(evaluate(node))) continue;
    std::vector<std::string> args;
    for (Expr a : node.args()) args.push_back(fmt::format("{}", evaluate(a)));
    std::string name(symbolic::info(node.kind()).name);
    if (node.kind() == symbolic::Kind::Pow) {
      name = node.arg(1) == Expr(symbolic::Number(1, 2)) ? "sqrt" : "pow";
      if (name == "sqrt") args.pop_back();  // the exponent 1/2
    }
    return fmt::format("{}({})", name, fmt::join(args, ", "));
  }
  return std::string("its value");  // unreachable: a non-finite value comes from some operation
}

}  // namespace

Body::Body(std::string name) : name_(std::move(name)), mass_(0), inertia_{} {}

Expr Scalar::to_expr(std::string_view what) const {
  if (!is_number_) return expr_;
  if (!std::isfinite(number_))
    throw ModelError(fmt::format("{} is not finite ({})", what, number_));
  return Expr(number_);
}

Body& Body::mass(Scalar m) {
  mass_ = m.to_expr(fmt::format("body '{}': mass", name_));
  return *this;
}

Body& Body::inertia(Scalar ixx, Scalar iyy, Scalar izz) {
  const Expr o(0);
  auto moment = [&](const Scalar& v, const char* axis) {
    return v.to_expr(fmt::format("body '{}': inertia {}", name_, axis));
  };
  inertia_ = {moment(ixx, "Ixx"), o, o, o, moment(iyy, "Iyy"), o, o, o, moment(izz, "Izz")};
  return *this;
}

Body& Body::inertia(const Mat3& tensor) {
  inertia_ = tensor;
  return *this;
}

Body& Body::motion(const Transform& T0G) {
  motion_ = T0G;
  has_motion_ = true;
  return *this;
}

Body& Body::relative_to(std::string_view reference) {
  reference_ = std::string(reference);
  return *this;
}

Model::Model(std::string name)
    : name_(std::move(name)), gravity_(zero3()), time_(declare("t", SymbolKind::Time)) {
  check_builder_name(name_, "model");
}

bool Model::is_declared(Expr s) const {
  if (s == time_) return true;
  auto in = [&](const auto& list, auto field) {
    return std::any_of(list.begin(), list.end(),
                       [&](const auto& item) { return item.*field == s; });
  };
  return in(coordinates_, &Coordinate::q) || in(dependents_, &Dependent::symbol) ||
         in(parameters_, &Parameter::symbol);
}

void Model::check_declared(Expr e, std::string_view where) const {
  if (e.is_number()) return;
  for (Expr s : symbolic::free_symbols(std::span<const Expr>(&e, 1))) {
    if (!is_declared(s)) {
      throw ModelError(fmt::format("{} uses '{}', which is not declared in model '{}' before it",
                                   where, s.name(), name_));
    }
  }
}

Expr Model::coordinate(std::string_view name) {
  check_builder_name(name, "coordinate");
  if (is_declared(declare(name, SymbolKind::Variable))) {
    throw ModelError(fmt::format("coordinate '{}' is declared twice", name));
  }
  auto [rate, acceleration] = derivative_names(name);
  // Before the implicit dependent parameters: x = (q, p).
  const auto at =
      coordinates_.insert(coordinates_.end() - static_cast<std::ptrdiff_t>(num_implicit_),
                          {declare(name, SymbolKind::Variable), declare(rate, SymbolKind::Rate),
                           declare(acceleration, SymbolKind::Acceleration)});
  return at->q;
}

Expr Model::implicit_dependent(std::string_view name, double guess) {
  check_builder_name(name, "implicit dependent parameter");
  if (!std::isfinite(guess)) {
    throw ModelError(
        fmt::format("implicit dependent parameter '{}': guess {} is not finite", name, guess));
  }
  if (is_declared(declare(name, SymbolKind::Variable)))
    throw ModelError(fmt::format("implicit dependent parameter '{}' is declared twice", name));
  auto [rate, acceleration] = derivative_names(name);
  coordinates_.push_back({.q = declare(name, SymbolKind::Variable),
                          .qd = declare(rate, SymbolKind::Rate),
                          .qdd = declare(acceleration, SymbolKind::Acceleration),
                          .initial = guess,
                          .implicit = true});
  ++num_implicit_;
  return coordinates_.back().q;
}

void Model::check_loop_name(std::string_view name) const {
  check_builder_name(name, "loop");
  if (std::any_of(loops_.begin(), loops_.end(), [&](const Loop& l) { return l.name == name; }))
    throw ModelError(fmt::format("loop '{}' is declared twice", name));
}

void Model::constraint(std::string_view name, std::vector<Expr> equations) {
  add_loop(name, std::move(equations));
}

Loop& Model::add_loop(std::string_view name, std::vector<Expr> equations, std::vector<int>* kept) {
  check_loop_name(name);
  Loop loop;
  loop.name = std::string(name);
  symbolic::Simplifier simplify;
  for (std::size_t k = 0; k < equations.size(); ++k) {
    const Expr g = equations[k];
    check_declared(g, fmt::format("loop '{}' equation {}", name, k));
    // Identically zero: no equation (a planar mechanism's z); a nonzero constant: never satisfied.
    const Expr simplified = g.is_number() ? g : simplify(g);
    if (simplified.is_number()) {
      if (simplified == Expr(0)) continue;
      throw ModelError(fmt::format("loop '{}' equation {} is the constant {}, never 0", name, k,
                                   simplified.str()));
    }
    loop.equations.push_back(g);
    if (kept) kept->push_back(static_cast<int>(k));
  }
  if (loop.equations.empty())
    throw ModelError(fmt::format("loop '{}' has no equation that is not identically 0", name));
  loops_.push_back(std::move(loop));
  return loops_.back();
}

Transform::Pose Model::absolute_pose(std::string_view name, std::string_view loop) const {
  const int i = body_index(name);
  if (i < 0)
    throw ModelError(fmt::format("loop '{}' closes on '{}', which is not a body", loop, name));
  const Body& b = bodies_[i];
  if (!b.has_motion()) {
    throw ModelError(
        fmt::format("loop '{}' closes on body '{}', which has no motion yet (give it before "
                    "close_loop)",
                    loop, name));
  }
  Transform::Pose pose = b.motion().pose();
  if (!b.reference()) return pose;
  const Transform::Pose base = absolute_pose(*b.reference(), loop);
  return {base.R * pose.R, base.x + base.R * pose.x, {}};
}

void Model::close_loop(std::string_view name, std::string_view body_a, const Vec3& point_a,
                       std::string_view body_b, const Vec3& point_b) {
  check_loop_name(name);
  topological_order();  // unknown references and cycles, before following them
  const Transform::Pose a = absolute_pose(body_a, name), b = absolute_pose(body_b, name);
  const Vec3 point = a.x + a.R * point_a;
  const Vec3 gap = point - (b.x + b.R * point_b);
  std::vector<int> axes;
  Loop& loop = add_loop(name, {gap[0], gap[1], gap[2]}, &axes);
  loop.body_a = body_index(body_a);
  loop.body_b = body_index(body_b);
  loop.point = point;
  loop.axes = std::move(axes);
}

std::vector<Expr> Model::coordinates(int n, std::string_view prefix) {
  std::vector<Expr> q;
  const int first = static_cast<int>(coordinates_.size());
  for (int i = 0; i < n; ++i) q.push_back(coordinate(fmt::format("{}{}", prefix, first + i)));
  return q;
}

Expr Model::parameter(std::string_view name, double value, bool runtime) {
  check_builder_name(name, "parameter");
  if (!std::isfinite(value))
    throw ModelError(fmt::format("parameter '{}' = {} is not finite", name, value));
  if (!(runtime || runtime_parameters_)) return Expr(value);
  const Expr s = declare(name, SymbolKind::Parameter);
  if (is_declared(s)) throw ModelError(fmt::format("parameter '{}' is declared twice", name));
  parameters_.push_back({s, value});
  return s;
}

Expr Model::dependent(std::string_view name, Expr expression) {
  check_builder_name(name, "dependent parameter");
  check_declared(expression, fmt::format("dependent parameter '{}'", name));
  if (inline_dependents_) {
    inlined_dependents_.push_back({std::string(name), expression});
    return expression;
  }
  const Expr s = declare(name, SymbolKind::Dependent);
  if (is_declared(s))
    throw ModelError(fmt::format("dependent parameter '{}' is declared twice", name));
  auto [rate, acceleration] = derivative_names(name);
  dependents_.push_back({s, declare(rate, SymbolKind::DependentRate),
                         declare(acceleration, SymbolKind::DependentAcceleration), expression});
  return s;
}

Body& Model::body(std::string_view name) {
  check_builder_name(name, "body");
  if (body_index(name) >= 0) throw ModelError(fmt::format("body '{}' is declared twice", name));
  bodies_.push_back(Body(std::string(name)));
  return bodies_.back();
}

void Model::gravity(Scalar gx, Scalar gy, Scalar gz) {
  gravity_ = {gx.to_expr("gravity x"), gy.to_expr("gravity y"), gz.to_expr("gravity z")};
  for (Expr g : gravity_) check_declared(g, "gravity");
}

void Model::initial(Expr q, double value, double rate) {
  for (Coordinate& c : coordinates_) {
    if (c.q == q) {
      c.initial = value;
      c.initial_rate = rate;
      return;
    }
  }
  throw ModelError(fmt::format("initial: '{}' is not a coordinate of model '{}'", q.str(), name_));
}

symbolic::RateMap Model::rates() const {
  symbolic::RateMap rates;
  for (const Coordinate& c : coordinates_) rates.emplace(c.q, c.qd), rates.emplace(c.qd, c.qdd);
  for (const Dependent& d : dependents_) {
    rates.emplace(d.symbol, d.rate), rates.emplace(d.rate, d.acceleration);
  }
  return rates;
}

int Model::body_index(std::string_view name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].name() == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<bool> Model::referenced() const {
  std::vector<bool> out(bodies_.size(), false);
  for (int r : reference_indices()) {
    if (r >= 0) out[r] = true;
  }
  return out;
}

std::vector<int> Model::reference_indices() const {
  std::vector<int> refs;
  for (const Body& b : bodies_) {
    if (!b.reference()) {
      refs.push_back(-1);
      continue;
    }
    const int r = body_index(*b.reference());
    if (r < 0)
      throw ModelError(fmt::format("body '{}' is relative to '{}', which is not a body", b.name(),
                                   *b.reference()));
    refs.push_back(r);
  }
  return refs;
}

Model Model::with_shared_motions_relative() const {
  Model out = *this;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Transform& motion = bodies_[i].motion();
    const Body* base = nullptr;
    for (const Body& other : bodies_) {
      const std::size_t n = other.motion().steps().size();
      const bool shares = n < motion.steps().size() &&
                          other.reference() == bodies_[i].reference() &&
                          other.motion().has_rotation() && motion.starts_with(other.motion());
      if (shares && (base == nullptr || n > base->motion().steps().size())) base = &other;
    }
    if (base == nullptr) continue;
    out.bodies_[i].motion_ = motion.after(base->motion().steps().size());
    out.bodies_[i].reference_ = base->name();
  }
  return out;
}

std::vector<int> Model::topological_order() const {
  const std::vector<int> refs = reference_indices();
  const int n = static_cast<int>(bodies_.size());
  std::vector<int> state(n, 0);  // 0 unvisited, 1 in progress, 2 done
  std::vector<int> order;
  for (int start = 0; start < n; ++start) {
    std::vector<int> chain;  // walk up the references, then emit top-down
    int b = start;
    while (b >= 0 && state[b] == 0) {
      state[b] = 1;
      chain.push_back(b);
      b = refs[b];
    }
    if (b >= 0 && state[b] == 1) {
      std::string cycle = bodies_[b].name();
      for (int c = refs[b]; c != b; c = refs[c]) cycle += " -> " + bodies_[c].name();
      throw ModelError(
          fmt::format("relative motions form a cycle: {} -> {}", cycle, bodies_[b].name()));
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      state[*it] = 2;
      order.push_back(*it);
    }
  }
  return order;
}

void Model::validate() const {
  // In this order (docs/errors.md): the first culprit found is reported.
  static constexpr void (Model::*kChecks[])()
      const = {&Model::validate_structure, &Model::validate_bodies,
               &Model::validate_gravity,   &Model::validate_coordinates_move_bodies,
               &Model::validate_loops,     &Model::validate_initial_configuration};
  for (auto check : kChecks) (this->*check)();
}

void Model::validate_structure() const {
  if (num_independent() == 0) throw ModelError(fmt::format("model '{}' has no coordinate", name_));
  if (bodies_.empty()) throw ModelError(fmt::format("model '{}' has no body", name_));
  topological_order();  // unknown references and cycles
}

void Model::validate_bodies() const {
  for (const Body& b : bodies_) validate_body(b);
}

// A body as the runtime will check it at construction (runtime/model.cpp),
// with the parameters at their defaults.
void Model::validate_body(const Body& b) const {
  const std::string where = fmt::format("body '{}'", b.name());
  if (!b.has_motion()) throw ModelError(fmt::format("{} has no motion", where));
  const std::string motion = where + " motion";
  for (const Transform::Step& s : b.motion().steps()) {
    for (Expr e : s.displacement) check_declared(e, motion);
    check_declared(s.angle, motion);
  }
  check_declared(b.mass(), where + " mass");
  const std::string inertia = where + " inertia";
  for (Expr e : b.inertia()) check_declared(e, inertia);
  // k: the entry of the inertia tensor, -1 for the mass (named only in the error).
  const auto constant = [&](Expr e, int k) {
    if (const auto s = non_constant_symbol(e)) {
      const std::string quantity =
          k < 0 ? std::string("mass") : fmt::format("inertia I{}{}", k / 3, k % 3);
      throw ModelError(
          fmt::format("{}: {} depends on {}; a mass or inertia may use only constants and run-time "
                      "parameters",
                      where, quantity, describe_symbol(*s)));
    }
  };
  constant(b.mass(), -1);
  for (int k = 0; k < 9; ++k) constant(b.inertia()[k], k);
  symbolic::Bindings<double> values;
  for (const Parameter& p : parameters_) values.emplace(p.symbol, p.value);
  symbolic::Evaluator<double> evaluate(values);
  std::array<double, 9> I{};
  for (int k = 0; k < 9; ++k) I[k] = evaluate(b.inertia()[k]);
  const std::string problem = symdyn::detail::inertia_problem(evaluate(b.mass()), I);
  if (!problem.empty()) throw ModelError(fmt::format("{}: {}", where, problem));
}

// The emitted gravity is a constant array: numbers only.
void Model::validate_gravity() const {
  for (int k = 0; k < 3; ++k) {
    const Expr g = gravity_[k];
    if (g.is_number()) continue;
    const auto symbols = symbolic::free_symbols(std::span<const Expr>(&g, 1));
    throw ModelError(fmt::format("gravity {}: '{}' depends on {}; gravity must be a number",
                                 "xyz"[k], g.str(), describe_symbol(symbols.front())));
  }
}

// A coordinate that appears in no body's motion, directly or through dependent
// parameters, moves nothing: its row of the mass matrix would be zero.
void Model::validate_coordinates_move_bodies() const {
  std::vector<Expr> motions;
  for (const Body& b : bodies_) {
    for (const Transform::Step& s : b.motion().steps()) {
      motions.insert(motions.end(), s.displacement.begin(), s.displacement.end());
      motions.push_back(s.angle);
    }
  }
  std::vector<Expr> used = symbolic::free_symbols(motions);
  // Dependent parameters are declared in order: the later ones first expand into the earlier ones.
  for (auto d = dependents_.rbegin(); d != dependents_.rend(); ++d) {
    if (std::find(used.begin(), used.end(), d->symbol) == used.end()) continue;
    for (Expr s : symbolic::free_symbols(std::span<const Expr>(&d->expression, 1)))
      used.push_back(s);
  }
  for (const Coordinate& c : coordinates_) {
    if (std::find(used.begin(), used.end(), c.q) == used.end()) {
      throw ModelError(
          fmt::format("coordinate '{}' moves no body: no body's position or rotation depends on it "
                      "(its mass matrix row would be zero)",
                      c.q.name()));
    }
  }
}

// Each dependent parameter, then each body's motion, evaluated at t = 0, q =
// the initial values and the parameters' defaults: an expression out of its
// domain there names the parameter or the body, and the function.
void Model::validate_initial_configuration() const {
  symbolic::Bindings<double> values;
  values.emplace(time_, 0.0);
  for (const Parameter& p : parameters_) values.emplace(p.symbol, p.value);
  for (const Coordinate& c : coordinates_) values.emplace(c.q, c.initial);
  // `owner` and `name` say where e is, formatted only for an error.
  const auto check = [&](Expr e, symbolic::Evaluator<double>& evaluate, const char* owner,
                         const std::string& name, const char* what) {
    if (const auto operation = undefined_operation(e, evaluate)) {
      throw ModelError(fmt::format(
          "{} '{}'{}: {} is not defined at the initial configuration (t = 0, coordinates "
          "at their initial values)",
          owner, name, what, *operation));
    }
  };
  for (const Dependent& d : dependents_) {
    symbolic::Evaluator<double> evaluate(values);
    check(d.expression, evaluate, "dependent parameter", d.symbol.name(), "");
    values.emplace(d.symbol, evaluate(d.expression));
  }
  symbolic::Evaluator<double> evaluate(values);
  for (const Body& b : bodies_) {
    for (const Transform::Step& s : b.motion().steps()) {
      for (Expr e : s.displacement) check(e, evaluate, "body", b.name(), " motion");
      check(s.angle, evaluate, "body", b.name(), " motion");
    }
  }
  for (const Loop& l : loops_) {
    for (Expr g : l.equations) check(g, evaluate, "loop", l.name, " equation");
  }
}

// The loops determine the implicit dependent parameters: as many equations
// as parameters, each loop depending on some of them and each of them on
// some loop (directly or through explicit dependent parameters).
void Model::validate_loops() const {
  if (loops_.empty() && num_implicit_ == 0) return;
  std::vector<std::string> implicit;
  for (const Coordinate& c : coordinates_) {
    if (c.implicit) implicit.push_back(c.q.name());
  }
  // The symbols of `e`, with those of the explicit dependent parameters it uses.
  const auto symbols = [&](Expr e) {
    std::vector<Expr> used = symbolic::free_symbols(std::span<const Expr>(&e, 1));
    for (auto d = dependents_.rbegin(); d != dependents_.rend(); ++d) {
      if (std::find(used.begin(), used.end(), d->symbol) == used.end()) continue;
      for (Expr s : symbolic::free_symbols(std::span<const Expr>(&d->expression, 1)))
        used.push_back(s);
    }
    return used;
  };
  std::vector<Expr> determined;
  std::size_t equations = 0;
  std::vector<std::string> counts;
  for (const Loop& l : loops_) {
    bool any = false;
    for (Expr g : l.equations) {
      for (Expr s : symbols(g)) {
        const auto c = std::find_if(coordinates_.begin(), coordinates_.end(),
                                    [&](const Coordinate& c) { return c.q == s && c.implicit; });
        if (c == coordinates_.end()) continue;
        any = true;
        determined.push_back(s);
      }
    }
    if (!any) {
      throw ModelError(fmt::format(
          "loop '{}' depends on no implicit dependent parameter: it would constrain the "
          "coordinates themselves (declare the parameters it determines with implicit_dependent)",
          l.name));
    }
    equations += l.equations.size();
    counts.push_back(fmt::format("loop '{}' ({} equation{})", l.name, l.equations.size(),
                                 l.equations.size() == 1 ? "" : "s"));
  }
  for (const Coordinate& c : coordinates_) {
    if (c.implicit && std::find(determined.begin(), determined.end(), c.q) == determined.end()) {
      throw ModelError(fmt::format(
          "implicit dependent parameter '{}' appears in no loop's equations (declare its loop "
          "with constraint or close_loop)",
          c.q.name()));
    }
  }
  if (equations != num_implicit_) {
    throw ModelError(fmt::format(
        "{} give{} {} equation{} for {} implicit dependent parameter{} ({}): as many independent "
        "equations as parameters are needed",
        fmt::join(counts, ", "), loops_.size() == 1 ? "s" : "", equations,
        equations == 1 ? "" : "s", num_implicit_, num_implicit_ == 1 ? "" : "s",
        fmt::join(implicit, ", ")));
  }
}

}  // namespace symdyn::model

namespace symdyn::model {

Model Definition::make(std::string_view variant) const {
  if (variants.empty()) throw ModelError(fmt::format("model '{}' declares no variant", name));
  const std::string chosen = variant.empty() ? variants.front() : std::string(variant);
  if (std::find(variants.begin(), variants.end(), chosen) == variants.end()) {
    throw ModelError(fmt::format("model '{}' has no variant '{}' (variants: {})", name, chosen,
                                 fmt::join(variants, ", ")));
  }
  Model m(name);
  try {
    build(m, chosen);
  } catch (const symbolic::SymbolicError&
               e) {  // a constant out of a function's domain, folded at construction
    throw ModelError(fmt::format("model '{}' variant '{}': {}", name, chosen, e.what()));
  }
  return m;
}

std::vector<Definition>& registry() {
  static std::vector<Definition> definitions;
  return definitions;
}

const Definition& find_definition(std::string_view name) {
  for (const Definition& d : registry()) {
    if (d.name == name) return d;
  }
  std::vector<std::string> names;
  for (const Definition& d : registry()) names.push_back(d.name);
  throw ModelError(fmt::format("no model named '{}' (known: {})", name, fmt::join(names, ", ")));
}

}  // namespace symdyn::model
