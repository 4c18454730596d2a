#include "elements.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ranges>
#include <string_view>

#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/element_parameters.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/gim_tyre.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace symdyn::sim {

using runtime::Kinematics;
using runtime::KinematicsLevel;
using runtime::Loads;
using runtime::State;
using runtime::Vec3;

Expression read_expression(const Node& node, const Resolver& resolver) {
  if (node.is_number()) return Expression::constant(node.number());
  const std::string text = node.string();
  try {
    return Expression::parse(text, resolver);
  } catch (const ExpressionError& e) {
    node.fail(e.what());
  }
}

namespace {

Vec3 vec3(const Node& n) {
  const auto v = n.numbers(3);
  return Vec3(v[0], v[1], v[2]);
}

// The constants of an element of `type` (runtime::element_parameters): each
// given one read as a number or 3, a required one missing refused at the
// element; their ranges are checked by the element's constructor.
runtime::ParameterValues read_parameters(const Node& node, std::string_view type) {
  runtime::ParameterValues values(type);
  for (const runtime::Parameter& p : values.row().parameters) {
    const auto n = node.optional(p.name);
    if (!n) continue;
    if (p.shape == runtime::ParameterShape::number) {
      values.set(p.name, n->number());
    } else {
      values.set(p.name, vec3(*n));
    }
  }
  if (const runtime::Parameter* p = values.missing()) {
    node.fail(fmt::format("missing key '{}' ({})", p->name, runtime::description(*p)));
  }
  return values;
}

// Reads the members of one element's object, resolving names against the model.
class Reader {
 public:
  Reader(const Node& node, const ElementContext& c, const runtime::ParameterValues* values)
      : node_(node), c_(c), values_(values) {}

  const Node& node() const { return node_; }
  // The element's constants (a type with constants only).
  const runtime::ParameterValues& values() const { return *values_; }
  std::string name() const { return node_["name"].string(); }
  int body(const Node& n) const {
    const std::string name = n.string();
    if (name == "ground") return runtime::ground;
    const auto& bodies = c_.names.model->body_names();
    const auto it = std::find(bodies.begin(), bodies.end(), name);
    if (it == bodies.end())
      n.fail(
          fmt::format("unknown body '{}' (bodies: {}, or ground)", name, fmt::join(bodies, ", ")));
    return static_cast<int>(it - bodies.begin());
  }
  int body(std::string_view key) const { return body(node_[key]); }
  // A body that moves: an element acting on the ground alone would do nothing.
  int moving_body(const Node& n, std::string_view what) const {
    const int b = body(n);
    if (b == runtime::ground)
      n.fail(fmt::format("{} on the ground moves nothing: name a body", what));
    return b;
  }
  int coordinate(const Node& n) const {
    const std::string name = n.string();
    const auto& q = c_.names.model->q_names();
    const auto it = std::find(q.begin(), q.end(), name);
    if (it == q.end())
      n.fail(fmt::format("unknown coordinate '{}' (coordinates: {})", name, fmt::join(q, ", ")));
    return static_cast<int>(it - q.begin());
  }
  int coordinate(std::string_view key) const { return coordinate(node_[key]); }
  // An element between two frames of the ground, or of one rigid body, pushes
  // nothing: its forces cancel.
  void distinct_bodies(int a, int b, std::string_view what) const {
    if (a != b) return;
    const Node at = node_["b"]["body"];
    at.fail(a == runtime::ground
                ? fmt::format("{} between two points of the ground moves nothing", what)
                : fmt::format("{} with both ends on body '{}' moves nothing (its forces cancel)",
                              what, at.string()));
  }
  // {"body", "point"}: a body point.
  runtime::BodyPoint body_point(std::string_view key) const {
    const Node p = node_[key];
    p.allow_only({"body", "point"});
    return {body(p["body"]), p.has("point") ? vec3(p["point"]) : Vec3::Zero()};
  }
  // {"point", "normal"}: a plane (default: z = 0, normal +z).
  runtime::Plane plane(std::string_view key) const {
    runtime::Plane plane;
    const auto n = node_.optional(key);
    if (!n) return plane;
    n->allow_only({"point", "normal"});
    if (n->has("point")) plane.point = vec3((*n)["point"]);
    if (n->has("normal")) {
      const Node normal = (*n)["normal"];
      plane.normal = vec3(normal);
      if (!(plane.normal.norm() > 0.0)) normal.fail("expected a non-zero normal");
      plane.normal.normalize();
    }
    return plane;
  }
  Expression expression(std::string_view key, const Scope& scope) const {
    return read_expression(node_[key], make_resolver(c_.names, scope, c_.table));
  }
  const ElementContext& context() const { return c_; }

 private:
  const Node& node_;
  const ElementContext& c_;
  const runtime::ParameterValues* values_;
};

// Reads the kinematics up to the level the symbols of its laws need.
KinematicsLevel level_of(const std::vector<const Expression*>& laws, const SymbolTable& table) {
  for (const Expression* e : laws) {
    for (int s : e->symbols()) {
      if (table[s].source == Source::body) return KinematicsLevel::velocities;
    }
  }
  return KinematicsLevel::none;
}

// Whether each symbol the laws read has its derivatives with respect to q and qd.
bool differentiable(const std::vector<const Expression*>& laws, const LawEnvironment& env) {
  return std::all_of(laws.begin(), laws.end(), [&](const Expression* e) {
    return std::all_of(e->symbols().begin(), e->symbols().end(),
                       [&](int s) { return env.differentiable(s); });
  });
}

// A law's value, and added to row `row` of dq and dqd its derivatives with respect to q
// and qd: ∂law/∂q_k = Σ_s ∂law/∂s·∂s/∂q_k, the law's gradient by forward mode
// (Expression::evaluate, into `gradient`, as long as its symbols), the symbols' from
// the state and the kinematics' derivatives dk (env set at the state). A gradient
// that is not finite (sqrt at 0) is refused, naming the element and its law.
double add_law_derivatives(const std::string& element, const Expression& law,
                           const LawEnvironment& env, const runtime::KinematicsDerivatives& dk,
                           std::vector<double>& gradient, runtime::Matrix& dq, runtime::Matrix& dqd,
                           int row) {
  const double value = law.evaluate(env, gradient.data());
  const auto& symbols = law.symbols();
  if (!std::all_of(gradient.begin(), gradient.begin() + static_cast<long>(symbols.size()),
                   [](double d) { return std::isfinite(d); })) {
    throw runtime::NumericError(
        fmt::format("{}: the derivative of '{}' is not finite here (its value: {})", element,
                    law.text(), value));
  }
  for (std::size_t i = 0; i < symbols.size(); ++i) {
    if (gradient[i] == 0.0) continue;
    for (int kk = 0; kk < dq.cols(); ++kk) {
      double d_dq = 0.0, d_dqd = 0.0;
      env.derivatives(symbols[i], dk, kk, d_dq, d_dqd);
      dq(row, kk) += gradient[i] * d_dq;
      dqd(row, kk) += gradient[i] * d_dqd;
    }
  }
  return value;
}

// A generalized force given by an expression, on one or more coordinates;
// exact derivatives where each symbol it reads has its own.
class ExpressionForce : public runtime::ForceElement {
 public:
  ExpressionForce(std::string name, std::vector<int> coordinates, Expression law,
                  const SymbolTable& table, const std::vector<double>& variables)
      : label_("coordinate force '" + name + "'"),
        coordinates_(std::move(coordinates)),
        law_(std::move(law)),
        env_(table, variables),
        level_(level_of({&law_}, table)),
        gradient_(law_.symbols().size()) {}
  std::string name() const override { return label_; }
  KinematicsLevel reads() const override { return level_; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override {
    env_.set(s, k);
    const double Q = law_.evaluate(env_);
    for (int j : coordinates_) loads.add_generalized(j, Q);
  }
  runtime::LoadDerivatives load_derivatives() const override {
    using enum runtime::LoadDerivatives;
    if (!differentiable({&law_}, env_)) return differenced;
    return level_ == KinematicsLevel::none ? exact : exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k,
                            const runtime::KinematicsDerivatives& dk, runtime::Matrix& dQ_dq,
                            runtime::Matrix& dQ_dqd) const override {
    env_.set(s, k);
    const auto nq = s.q.size();
    dq_.setZero(1, nq);
    dqd_.setZero(1, nq);
    add_law_derivatives(label_, law_, env_, dk, gradient_, dq_, dqd_, 0);
    for (int j : coordinates_) {
      dQ_dq.row(j) += dq_;
      dQ_dqd.row(j) += dqd_;
    }
  }

 private:
  std::string label_;
  std::vector<int> coordinates_;
  Expression law_;
  mutable LawEnvironment env_;
  KinematicsLevel level_;
  mutable std::vector<double> gradient_;  // of the law, with respect to its symbols
  mutable runtime::Matrix dq_, dqd_;      // its derivatives (1 x nq)
};

// The loads an element applies at a state, into a buffer of its own.
class LoadProbe {
 public:
  LoadProbe(const runtime::ForceElement& e, const runtime::Model& m)
      : e_(e), loads_(m.nq(), m.nbody()) {}
  const Loads& at(const State& s, const Kinematics& k) const {
    loads_.clear();
    e_.apply(s, k, loads_);
    return loads_;
  }

 private:
  const runtime::ForceElement& e_;
  mutable Loads loads_;
};

// fx, fy, fz: the force the element exerts on `body` (global axes).
void add_force_quantities(ScenarioElement& e, int body, int other, const runtime::Model& m) {
  auto probe = std::make_shared<LoadProbe>(e.inner(), m);
  for (int axis = 0; axis < 3; ++axis) {
    e.add_quantity(std::string("f") + "xyz"[axis],
                   [probe, body, other, axis](const State& s, const Kinematics& k) {
                     const Loads& l = probe->at(s, k);
                     return body != runtime::ground    ? l.F(axis, body)
                            : other != runtime::ground ? -l.F(axis, other)
                                                       : 0.0;
                   });
  }
}

// Q: the generalized force on coordinate j.
void add_generalized_quantity(ScenarioElement& e, int j, const runtime::Model& m) {
  auto probe = std::make_shared<LoadProbe>(e.inner(), m);
  e.add_quantity("Q",
                 [probe, j](const State& s, const Kinematics& k) { return probe->at(s, k).Q(j); });
}

template <class E>
std::shared_ptr<ScenarioElement> wrap(const Reader& r, std::shared_ptr<E> inner) {
  return std::make_shared<ScenarioElement>(
      r.node()["name"].string(), std::move(inner),
      r.node().has("enabled") ? r.node()["enabled"].boolean() : true);
}

std::shared_ptr<ScenarioElement> coordinate_spring_damper(const Reader& r) {
  const int j = r.coordinate("coordinate");
  auto e = wrap(r, runtime::make_coordinate_spring_damper(r.name(), j, r.values()));
  add_generalized_quantity(*e, j, *r.context().names.model);
  return e;
}

std::shared_ptr<ScenarioElement> coordinate_force(const Reader& r) {
  std::vector<int> coordinates;
  const Node c = r.node()["coordinates"];
  if (c.is_string()) {
    coordinates.push_back(r.coordinate(c));
  } else {
    for (const Node& n : c.elements()) {
      const int j = r.coordinate(n);
      if (std::find(coordinates.begin(), coordinates.end(), j) != coordinates.end()) {
        n.fail(fmt::format("coordinate '{}' is listed twice: its force would be applied twice",
                           n.string()));
      }
      coordinates.push_back(j);
    }
    if (coordinates.empty()) c.fail("expected at least one coordinate");
  }
  auto e = wrap(r, std::make_shared<ExpressionForce>(r.node()["name"].string(), coordinates,
                                                     r.expression("value", Scope{}),
                                                     r.context().table, r.context().variables));
  add_generalized_quantity(*e, coordinates.front(), *r.context().names.model);
  return e;
}

std::shared_ptr<ScenarioElement> coordinate_tracking(const Reader& r) {
  const int j = r.coordinate("coordinate");
  // References are functions of time (and the variables): the runtime's
  // element calls them with t alone.
  const Scope time_only{.time = true, .state = false};
  auto env = std::make_shared<LawEnvironment>(r.context().table, r.context().variables);
  auto stub = std::make_shared<State>();
  auto kin = std::make_shared<Kinematics>();
  const auto function = [&](std::string_view key) -> runtime::CoordinateTracking::Reference {
    if (!r.node().has(key)) return nullptr;
    auto e = std::make_shared<Expression>(r.expression(key, time_only));
    return [e, env, stub, kin](double t) {
      stub->t = t;
      env->set(*stub, *kin);
      return e->evaluate(*env);
    };
  };
  auto reference = function("reference");
  auto e = wrap(r, runtime::make_coordinate_tracking(r.name(), j, reference,
                                                     function("reference_rate"), r.values()));
  add_generalized_quantity(*e, j, *r.context().names.model);
  e->add_quantity("reference",
                  [reference](const State& s, const Kinematics&) { return reference(s.t); });
  return e;
}

std::shared_ptr<ScenarioElement> point_spring_damper(const Reader& r) {
  const auto a = r.body_point("a"), b = r.body_point("b");
  r.distinct_bodies(a.body, b.body, "a spring");
  auto spring = runtime::make_point_spring_damper(r.name(), a, b, r.values());
  auto e = wrap(r, spring);
  e->add_quantity("length",
                  [spring](const State&, const Kinematics& k) { return spring->length(k); });
  add_force_quantities(*e, b.body, a.body, *r.context().names.model);
  return e;
}

std::shared_ptr<ScenarioElement> point_load(const Reader& r) {
  const auto at = r.body_point("at");
  if (at.body == runtime::ground)
    r.node()["at"]["body"].fail("a load on the ground moves nothing: name a body");
  const Scope law_scope{};
  std::vector<std::shared_ptr<Expression>> parts;
  for (const char* key : {"force", "torque"}) {
    const auto n = r.node().optional(key);
    if (n && (!n->json().is_array() || n->json().size() != 3))
      n->fail("expected an array of 3 numbers or expressions");
    for (int i = 0; i < 3; ++i) {
      parts.push_back(std::make_shared<Expression>(
          n ? read_expression(n->elements()[static_cast<std::size_t>(i)],
                              make_resolver(r.context().names, law_scope, r.context().table))
            : Expression::constant(0.0)));
    }
  }
  auto env = std::make_shared<LawEnvironment>(r.context().table, r.context().variables);
  runtime::PointLoad::Law law = [parts, env](const State& s, const Kinematics& k, Vec3& force,
                                             Vec3& torque) {
    env->set(s, k);
    for (int i = 0; i < 3; ++i) {
      force(i) = parts[static_cast<std::size_t>(i)]->evaluate(*env);
      torque(i) = parts[static_cast<std::size_t>(3 + i)]->evaluate(*env);
    }
  };
  // Its derivatives where each symbol its parts read has its own.
  std::vector<const Expression*> laws;
  std::size_t symbols = 0;
  for (const auto& p : parts) {
    laws.push_back(p.get());
    symbols = std::max(symbols, p->symbols().size());
  }
  runtime::PointLoad::LawDerivatives derivatives;
  if (differentiable(laws, *env)) {
    auto gradient = std::make_shared<std::vector<double>>(symbols);
    derivatives = [label = "load '" + r.name() + "'", parts, env, gradient](
                      const State& s, const Kinematics& k, const runtime::KinematicsDerivatives& dk,
                      Vec3& force, Vec3& torque, runtime::Matrix& dW_dq, runtime::Matrix& dW_dqd) {
      env->set(s, k);
      for (int i = 0; i < 6; ++i) {
        const double w = add_law_derivatives(label, *parts[static_cast<std::size_t>(i)], *env, dk,
                                             *gradient, dW_dq, dW_dqd, i);
        (i < 3 ? force(i) : torque(i - 3)) = w;
      }
    };
  }
  auto load = std::make_shared<runtime::PointLoad>(r.node()["name"].string(), at, std::move(law),
                                                   std::move(derivatives));
  auto e = wrap(r, load);
  add_force_quantities(*e, at.body, runtime::ground, *r.context().names.model);
  return e;
}

runtime::BodyFrame body_frame(const Reader& r, std::string_view key) {
  const Node f = r.node()[key];
  f.allow_only({"body", "origin", "axes"});
  runtime::BodyFrame frame;
  frame.body = r.body(f["body"]);
  if (f.has("origin")) frame.origin = vec3(f["origin"]);
  if (f.has("axes")) {
    const Node axes = f["axes"];
    const auto rows = axes.elements();
    if (rows.size() != 3) axes.fail("expected 3 axes (the columns of the frame, in body axes)");
    for (int c = 0; c < 3; ++c) frame.axes.col(c) = vec3(rows[static_cast<std::size_t>(c)]);
  }
  return frame;
}

std::shared_ptr<ScenarioElement> bushing(const Reader& r) {
  const auto a = body_frame(r, "a"), b = body_frame(r, "b");
  r.distinct_bodies(a.body, b.body, "a bushing");
  std::shared_ptr<runtime::Bushing> inner;
  try {
    inner = runtime::make_bushing(r.name(), a, b, r.node().string_or("order", "xyz"), r.values());
  } catch (const runtime::PropertyError&) {
    throw;  // named at its key by make_element
  } catch (const runtime::ModelError& e) {
    r.node()["order"].fail(e.what());  // an order that is not a Cardan sequence
  }
  auto e = wrap(r, inner);
  for (int i = 0; i < 3; ++i) {
    e->add_quantity(std::string("d") + "xyz"[i], [inner, i](const State&, const Kinematics& k) {
      return inner->deflection(k).d(i);
    });
  }
  for (int i = 0; i < 3; ++i) {
    e->add_quantity(
        std::string("angle_") + "abc"[i],
        [inner, i](const State&, const Kinematics& k) { return inner->deflection(k).theta(i); });
  }
  add_force_quantities(*e, b.body, a.body, *r.context().names.model);
  return e;
}

std::shared_ptr<ScenarioElement> plane_contact(const Reader& r) {
  auto regularization = runtime::FrictionRegularization::linear;
  if (const auto reg = r.node().optional("regularization")) {
    const std::string name = reg->string();
    if (name != "linear" && name != "smooth")
      reg->fail(fmt::format("expected linear or smooth, found '{}'", name));
    if (name == "smooth") regularization = runtime::FrictionRegularization::smooth;
  }
  auto contact = runtime::make_plane_contact(r.name(), r.moving_body(r.node()["body"], "a contact"),
                                             r.plane("plane"), regularization, r.values());
  auto e = wrap(r, contact);
  e->add_quantity("normal_force", [contact](const State&, const Kinematics& k) {
    return contact->evaluate(k).normal_force;
  });
  e->add_quantity("penetration", [contact](const State&, const Kinematics& k) {
    return contact->evaluate(k).penetration;
  });
  for (int i = 0; i < 3; ++i) {
    e->add_quantity(std::string("f") + "xyz"[i], [contact, i](const State&, const Kinematics& k) {
      return contact->evaluate(k).force(i);
    });
  }
  return e;
}

std::shared_ptr<ScenarioElement> simple_tyre(const Reader& r) {
  auto tyre = runtime::make_simple_tyre(r.name(), r.moving_body(r.node()["body"], "a tyre"),
                                        r.plane("ground"), r.values());
  auto e = wrap(r, tyre);
  e->add_quantity("normal_force", [tyre](const State&, const Kinematics& k) {
    return tyre->evaluate(k).normal_force;
  });
  e->add_quantity("penetration", [tyre](const State&, const Kinematics& k) {
    return tyre->evaluate(k).penetration;
  });
  for (int i = 0; i < 3; ++i) {
    e->add_quantity(std::string("f") + "xyz"[i], [tyre, i](const State&, const Kinematics& k) {
      return tyre->evaluate(k).force(i);
    });
  }
  return e;
}

std::shared_ptr<ScenarioElement> gim_tyre(const Reader& r) {
  auto tyre = runtime::make_gim_tyre(r.name(), r.moving_body(r.node()["body"], "a tyre"),
                                     r.plane("ground"), r.values());
  auto e = wrap(r, tyre);
  using Result = runtime::GimTyre::Result;
  const std::pair<const char*, double (*)(const Result&)> quantities[] = {
      {"normal_force", [](const Result& x) { return x.Fz; }},
      {"penetration", [](const Result& x) { return x.penetration; }},
      {"slip_long", [](const Result& x) { return x.slip_long; }},
      {"slip_lat", [](const Result& x) { return x.slip_lat; }},
      {"camber", [](const Result& x) { return x.camber; }},
      {"fx", [](const Result& x) { return x.force(0); }},
      {"fy", [](const Result& x) { return x.force(1); }},
      {"fz", [](const Result& x) { return x.force(2); }},
      {"mz", [](const Result& x) { return x.moment(2); }},
  };
  for (const auto& [name, read] : quantities) {
    e->add_quantity(name, [tyre, read = read](const State&, const Kinematics& k) {
      return read(tyre->evaluate(k));
    });
  }
  return e;
}

// One row per element type: its name, what it acts on and its laws (the keys
// besides type, name, enabled and its constants, which are the runtime's
// table), listed before the constants and after them, whether it has
// constants, and its builder.
struct ElementType {
  const char* type;
  std::initializer_list<std::string_view> keys, keys_after;
  bool constants;
  std::shared_ptr<ScenarioElement> (*make)(const Reader& r);
};

const ElementType kElementTypes[] = {
    {"coordinate_spring_damper", {"coordinate"}, {}, true, coordinate_spring_damper},
    {"coordinate_force", {"coordinates", "value"}, {}, false, coordinate_force},
    {"coordinate_tracking",
     {"coordinate"},
     {"reference", "reference_rate"},
     true,
     coordinate_tracking},
    {"point_spring_damper", {"a", "b"}, {}, true, point_spring_damper},
    {"point_load", {"at", "force", "torque"}, {}, false, point_load},
    {"bushing", {"a", "b", "order"}, {}, true, bushing},
    {"plane_contact", {"body"}, {"plane", "regularization"}, true, plane_contact},
    {"simple_tyre", {"body"}, {"ground"}, true, simple_tyre},
    {"gim_tyre", {"body"}, {"ground"}, true, gim_tyre},
};

// The keys an element of this type takes besides type and name.
std::vector<std::string_view> members_of(const ElementType& t) {
  std::vector<std::string_view> out{"enabled"};
  out.insert(out.end(), t.keys.begin(), t.keys.end());
  if (t.constants) {
    for (const auto& p : runtime::element_parameters(t.type).parameters) out.push_back(p.name);
  }
  out.insert(out.end(), t.keys_after.begin(), t.keys_after.end());
  return out;
}

bool identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

}  // namespace

std::vector<std::string> element_types() {
  std::vector<std::string> out;
  for (const auto& t : kElementTypes) out.emplace_back(t.type);
  return out;
}

std::vector<std::string> element_members(std::string_view type) {
  const auto row = std::find_if(std::begin(kElementTypes), std::end(kElementTypes),
                                [&](const ElementType& t) { return type == t.type; });
  if (row == std::end(kElementTypes)) return {};
  const auto members = members_of(*row);
  return {members.begin(), members.end()};
}

std::shared_ptr<ScenarioElement> make_element(const Node& node, const ElementContext& context) {
  const Node type = node["type"];
  const std::string name = type.string();
  const auto row = std::find_if(std::begin(kElementTypes), std::end(kElementTypes),
                                [&](const ElementType& t) { return name == t.type; });
  if (row == std::end(kElementTypes)) {
    type.fail(fmt::format("unknown force element type '{}' (types: {})", name,
                          fmt::join(element_types(), ", ")));
  }
  std::vector<std::string_view> keys{"type", "name"};
  const auto members = members_of(*row);
  keys.insert(keys.end(), members.begin(), members.end());
  // allow_only takes an initializer list: check by hand with the same message.
  for (const auto& [key, member] : node.members()) {
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
    const auto close = runtime::close_names(key, keys);
    member.fail(fmt::format(
        "unknown key '{}' for a {} (expected: {}){}", key, name, fmt::join(keys, ", "),
        close.empty() ? "" : fmt::format("; did you mean {}?", fmt::join(close, " or "))));
  }
  const Node id = node["name"];
  if (!identifier(id.string()))
    id.fail(
        fmt::format("'{}' is not a name expressions can use (letters, digits, _)", id.string()));
  try {
    if (!row->constants) return row->make(Reader(node, context, nullptr));
    const runtime::ParameterValues values = read_parameters(node, name);
    return row->make(Reader(node, context, &values));
  } catch (const runtime::PropertyError& e) {
    // Named at its key ("a/axes": the key axes of the member a) when the file has it.
    Node at = node;
    for (const auto part : std::views::split(std::string_view(e.property()), '/')) {
      const std::string key(part.begin(), part.end());
      if (!at.has(key)) break;
      at = at[key];
    }
    at.fail(e.detail());
  } catch (const runtime::ModelError& e) {
    node.fail(e.what());  // what the runtime's constructor refused
  }
}

}  // namespace symdyn::sim
