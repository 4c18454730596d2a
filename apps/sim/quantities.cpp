#include "quantities.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace symdyn::sim {

using runtime::Kinematics;
using runtime::State;

namespace {

// Body attributes, in the order body_quantity() reads them.
constexpr std::array<const char*, 21> kBodyAttributes = {
    "x",  "y",   "z",   "vx",  "vy",  "vz",  "wx",  "wy",  "wz",  "ux", "uy",
    "uz", "R00", "R01", "R02", "R10", "R11", "R12", "R20", "R21", "R22"};
constexpr std::array<const char*, 4> kEnergies = {"kinetic_energy", "gravitational_energy",
                                                  "elastic_energy", "total_energy"};
constexpr std::array<const char*, 6> kMomenta = {"momentum_x",         "momentum_y",
                                                 "momentum_z",         "angular_momentum_x",
                                                 "angular_momentum_y", "angular_momentum_z"};

template <class List>
int index_of(const List& list, std::string_view name) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (name == list[i]) return static_cast<int>(i);
  }
  return -1;
}

std::string joined(const auto& list) {
  return fmt::format("{}", fmt::join(list, ", "));
}

// reaction.<loop>.Fx ..: every loop equation's reaction.
std::vector<std::string> loop_reaction_names(const runtime::Model& model) {
  std::vector<std::string> out;
  for (int k = 0; k < model.ncon(); ++k) out.push_back("reaction." + model.loop_reaction_name(k));
  return out;
}

// The names valid in a scope, for the message of an unknown one.
std::string valid_names(const Names& names, const Scope& scope) {
  std::vector<std::string> groups;
  if (scope.time) groups.emplace_back("t");
  if (scope.state) {
    groups.push_back(fmt::format("coordinates {} (rates <q>_dot{})", joined(names.model->q_names()),
                                 scope.accelerations ? ", accelerations <q>_ddot" : ""));
    groups.push_back(fmt::format("bodies {} as <body>.<{}>", joined(names.model->body_names()),
                                 joined(kBodyAttributes)));
  }
  if (scope.system) {
    groups.push_back(joined(kEnergies) + ", " + joined(kMomenta));
    if (scope.accelerations && names.model->has_joint_reactions())
      groups.push_back(
          fmt::format("reaction.<body>.<{}>", joined(runtime::Model::kReactionComponents)));
    if (scope.accelerations && names.model->has_loops())
      groups.push_back(fmt::format("loop reactions {}", joined(loop_reaction_names(*names.model))));
    std::vector<std::string> elements;
    for (const auto& e : *names.elements) elements.push_back(e->id());
    if (!elements.empty())
      groups.push_back(fmt::format("force elements {} as <element>.<quantity>", joined(elements)));
  }
  if (!names.variables.empty())
    groups.push_back(fmt::format("variables {}", joined(names.variables)));
  if (scope.run_constants) groups.emplace_back("rtol, atol, t_end");
  return fmt::format("{}", fmt::join(groups, "; "));
}

[[noreturn]] void unknown(const std::string& what, const std::string& valid) {
  throw ExpressionError(fmt::format("unknown {} (valid: {})", what, valid));
}

// reaction.<body>.<component>: needs the accelerations and the emitted joint_reactions.
int resolve_reaction(std::string_view name, const Names& names, const Scope& scope,
                     SymbolTable& table) {
  const std::string_view what = name.substr(name.find('.') + 1);
  const auto dot = what.rfind('.');
  const std::string_view body = what.substr(0, dot),
                         component = dot == std::string_view::npos ? "" : what.substr(dot + 1);
  if (!scope.system || !scope.accelerations) {
    throw ExpressionError(fmt::format(
        "'{}': joint reactions are not known here (outputs and checks read them)", name));
  }
  if (const int k = index_of(loop_reaction_names(*names.model), name);
      k >= 0 && index_of(names.model->body_names(), body) < 0) {
    return table.add({.source = Source::loop_reaction, .a = k});
  }
  if (!names.model->has_joint_reactions()) {
    throw ExpressionError(fmt::format(
        "'{}': model '{}' was generated without joint reactions (REACTIONS in symdyn_add_model, "
        "generator --reactions)",
        name, names.model->name()));
  }
  const int b = index_of(names.model->body_names(), body);
  if (b < 0)
    unknown(fmt::format("body '{}' in '{}'", body, name), joined(names.model->body_names()));
  const int c = index_of(runtime::Model::kReactionComponents, component);
  if (c < 0) {
    unknown(fmt::format("reaction component '{}' in '{}'", component, name),
            joined(runtime::Model::kReactionComponents));
  }
  return table.add({.source = Source::reaction, .a = b, .b = c});
}

int resolve_dotted(std::string_view name, const Names& names, const Scope& scope,
                   SymbolTable& table) {
  const auto dot = name.find('.');
  const std::string_view owner = name.substr(0, dot), attribute = name.substr(dot + 1);
  const auto& bodies = names.model->body_names();
  if (owner == "reaction" && index_of(bodies, owner) < 0)
    return resolve_reaction(name, names, scope, table);
  if (const int body = index_of(bodies, owner); body >= 0 && scope.state) {
    const int a = index_of(kBodyAttributes, attribute);
    if (a < 0)
      unknown(fmt::format("quantity '{}' of body '{}'", attribute, owner), joined(kBodyAttributes));
    return table.add({.source = Source::body, .a = body, .b = a});
  }
  if (scope.system) {
    const auto& elements = *names.elements;
    for (std::size_t e = 0; e < elements.size(); ++e) {
      if (elements[e]->id() != owner) continue;
      const int q = index_of(elements[e]->quantity_names(), attribute);
      if (q < 0) {
        unknown(fmt::format("quantity '{}' of force element '{}'", attribute, owner),
                joined(elements[e]->quantity_names()));
      }
      return table.add({.source = Source::element, .a = static_cast<int>(e), .b = q});
    }
  }
  unknown(fmt::format("name '{}'", name), valid_names(names, scope));
}

// A coordinate, its rate or its acceleration.
int resolve_coordinate(std::string_view name, const Names& names, const Scope& scope,
                       SymbolTable& table) {
  const auto& q = names.model->q_names();
  if (const int j = index_of(q, name); j >= 0) return table.add({.source = Source::q, .a = j});
  for (const auto& [suffix, source] :
       {std::pair{std::string_view("_dot"), Source::qd}, {"_ddot", Source::qdd}}) {
    if (name.size() <= suffix.size() || name.substr(name.size() - suffix.size()) != suffix)
      continue;
    const int j = index_of(q, name.substr(0, name.size() - suffix.size()));
    if (j < 0) continue;
    if (source == Source::qdd && !scope.accelerations) {
      throw ExpressionError(fmt::format(
          "'{}': accelerations are not known here (outputs and checks read them)", name));
    }
    return table.add({.source = source, .a = j});
  }
  return -1;
}

}  // namespace

ScenarioElement::ScenarioElement(std::string name,
                                 std::shared_ptr<const runtime::ForceElement> inner, bool enabled)
    : id_(std::move(name)), inner_(std::move(inner)), enabled_(enabled) {}

void ScenarioElement::apply(const State& s, const Kinematics& k, runtime::Loads& loads) const {
  if (enabled_) inner_->apply(s, k, loads);
}

void ScenarioElement::add_load_derivatives(const State& s, const Kinematics& k,
                                           const runtime::KinematicsDerivatives& dk,
                                           runtime::Matrix& dQ_dq, runtime::Matrix& dQ_dqd) const {
  if (enabled_) inner_->add_load_derivatives(s, k, dk, dQ_dq, dQ_dqd);
}

double ScenarioElement::potential_energy(const State& s, const Kinematics& k) const {
  return enabled_ ? inner_->potential_energy(s, k) : 0.0;
}

void ScenarioElement::add_quantity(std::string name, Quantity q) {
  quantity_names_.push_back(std::move(name));
  quantities_.push_back(std::move(q));
}

double ScenarioElement::quantity(int which, const State& s, const Kinematics& k) const {
  return enabled_ ? quantities_[static_cast<std::size_t>(which)](s, k) : 0.0;
}

int SymbolTable::add(const Symbol& s) {
  const auto it = std::find(symbols_.begin(), symbols_.end(), s);
  if (it != symbols_.end()) return static_cast<int>(it - symbols_.begin());
  symbols_.push_back(s);
  return static_cast<int>(symbols_.size() - 1);
}

int resolve_name(std::string_view name, const Names& names, const Scope& scope,
                 SymbolTable& table) {
  if (const int v = index_of(names.variables, name); v >= 0)
    return table.add({.source = Source::variable, .a = v});
  if (scope.time && name == "t") return table.add({.source = Source::time});
  if (scope.state) {
    if (const int c = resolve_coordinate(name, names, scope, table); c >= 0) return c;
  }
  if (name.find('.') != std::string_view::npos) return resolve_dotted(name, names, scope, table);
  if (scope.system) {
    if (const int e = index_of(kEnergies, name); e >= 0)
      return table.add({.source = Source::energy, .a = e});
    if (const int m = index_of(kMomenta, name); m >= 0)
      return table.add({.source = Source::momentum, .a = m});
  }
  if (scope.run_constants) {
    for (const auto& [constant, value] :
         {std::pair{"rtol", names.rtol}, {"atol", names.atol}, {"t_end", names.t_end}}) {
      if (name == constant) return table.add({.source = Source::constant, .constant = value});
    }
  }
  unknown(fmt::format("name '{}'", name), valid_names(names, scope));
}

Resolver make_resolver(const Names& names, const Scope& scope, SymbolTable& table) {
  Resolver r;
  r.symbol = [&names, scope, &table](std::string_view name) {
    return resolve_name(name, names, scope, table);
  };
  return r;
}

double body_quantity(const Kinematics& k, int body, int attribute) {
  if (attribute < 3) return k.x(body)(attribute);
  if (attribute < 6) return k.v(body)(attribute - 3);
  if (attribute < 9) return k.w(body)(attribute - 6);
  if (attribute < 12) return k.R(body).col(attribute - 9).dot(k.v(body));  // (R^T v)_i
  const int r = attribute - 12;
  return k.R(body)(r / 3, r % 3);
}

// x: ∂x/∂q = dv/dqd; v, w: the kinematics' derivatives; u = Rᵀv: ∂u/∂q_k =
// Rᵀ(∂v/∂q_k + v × dw_k) since ∂R/∂q_k = skew(dw_k)·R, ∂u/∂qd_k = Rᵀ·dv_k; R:
// the columns turn, ∂R.col(c)/∂q_k = dw_k × R.col(c).
void body_quantity_derivatives(const Kinematics& k, const runtime::KinematicsDerivatives& dk,
                               int body, int attribute, int kk, double& d_dq, double& d_dqd) {
  const int c = attribute % 3;
  d_dqd = 0.0;
  if (attribute < 3) {
    d_dq = k.dv_dqd(body, kk)(c);
  } else if (attribute < 6) {
    d_dq = dk.dv_dq(body, kk)(c);
    d_dqd = k.dv_dqd(body, kk)(c);
  } else if (attribute < 9) {
    d_dq = dk.dw_dq(body, kk)(c);
    d_dqd = k.dw_dqd(body, kk)(c);
  } else if (attribute < 12) {
    const auto axis = k.R(body).col(c);
    d_dq = axis.dot(dk.dv_dq(body, kk) + k.v(body).cross(k.dw_dqd(body, kk)));
    d_dqd = axis.dot(k.dv_dqd(body, kk));
  } else {
    const int r = (attribute - 12) / 3, col = (attribute - 12) % 3;
    d_dq = k.dw_dqd(body, kk).cross(runtime::Vec3(k.R(body).col(col)))(r);
  }
}

SampleEnvironment::SampleEnvironment(runtime::MultibodySystem& system, const SymbolTable& table,
                                     const std::vector<std::shared_ptr<ScenarioElement>>& elements,
                                     const std::vector<double>& variables,
                                     const std::vector<double>& statistics)
    : system_(system),
      table_(table),
      elements_(elements),
      variables_(variables),
      statistics_(statistics) {}

void SampleEnvironment::set(const State& s, const runtime::Vector& qdd) {
  s_ = &s;
  qdd_ = &qdd;
  have_kinematics_ = have_energies_ = have_momentum_ = have_reactions_ = have_loop_reactions_ =
      have_extended_ = false;
}

const State& SampleEnvironment::tree_state() const {
  if (!system_.model().has_loops()) return *s_;
  // The implicit dependent parameters solved, with their rates and accelerations.
  if (!have_extended_) {
    extended_ = system_.extended_state(*s_);
    xdd_ = qdd_->size() == s_->q.size() ? system_.extended_accelerations(*s_, *qdd_)
                                        : runtime::Vector::Zero(extended_.q.size());
  }
  have_extended_ = true;
  return extended_;
}

double SampleEnvironment::coordinate(int j, int order) const {
  if (j < s_->q.size()) {
    if (order == 0) return s_->q(j);
    if (order == 1) return s_->qd(j);
    return qdd_->size() > j ? (*qdd_)(j) : 0.0;
  }
  const State& x = tree_state();
  return order == 0 ? x.q(j) : order == 1 ? x.qd(j) : xdd_(j);
}

const Kinematics& SampleEnvironment::kinematics() const {
  // energies() and momentum() evaluate the system's kinematics too: the
  // buffer holds this instant's whenever one of them has run.
  if (!have_kinematics_) system_.evaluate_kinematics(*s_);
  have_kinematics_ = true;
  return system_.kinematics();
}

double SampleEnvironment::value(int symbol) const {
  const Symbol& sym = table_[symbol];
  switch (sym.source) {
    case Source::time:
      return s_->t;
    case Source::q:
      return coordinate(sym.a, 0);
    case Source::qd:
      return coordinate(sym.a, 1);
    case Source::qdd:
      return coordinate(sym.a, 2);
    case Source::body:
      return body_quantity(kinematics(), sym.a, sym.b);
    case Source::energy: {
      if (!have_energies_) energies_ = system_.energies(*s_);
      have_energies_ = true;
      have_kinematics_ = false;
      const double e[] = {energies_.kinetic, energies_.gravitational, energies_.elastic,
                          energies_.total()};
      return e[sym.a];
    }
    case Source::momentum: {
      if (!have_momentum_) momentum_ = system_.momentum(*s_);
      have_momentum_ = true;
      have_kinematics_ = false;
      return sym.a < 3 ? momentum_.linear(sym.a) : momentum_.angular(sym.a - 3);
    }
    case Source::reaction: {
      if (!have_reactions_) {
        if (qdd_->size() == s_->q.size()) {
          system_.joint_reactions(*s_, *qdd_, reactions_);
        } else {
          system_.joint_reactions(*s_, reactions_);
        }
      }
      have_reactions_ = true;
      have_kinematics_ = false;
      return reactions_(sym.b, sym.a);
    }
    case Source::loop_reaction: {
      if (!have_loop_reactions_) {
        if (qdd_->size() == s_->q.size()) {
          system_.loop_reactions(*s_, *qdd_, loop_reactions_);
        } else {
          system_.loop_reactions(*s_, loop_reactions_);
        }
      }
      have_loop_reactions_ = true;
      have_kinematics_ = false;
      return loop_reactions_(sym.a);
    }
    case Source::element:
      return elements_[static_cast<std::size_t>(sym.a)]->quantity(sym.b, tree_state(),
                                                                  kinematics());
    case Source::variable:
      return variables_[static_cast<std::size_t>(sym.a)];
    case Source::constant:
      return sym.constant;
    case Source::statistic:
      return statistics_[static_cast<std::size_t>(sym.a)];
  }
  return 0.0;
}

double LawEnvironment::value(int symbol) const {
  const Symbol& sym = table_[symbol];
  switch (sym.source) {
    case Source::time:
      return s_->t;
    case Source::q:
      return s_->q(sym.a);
    case Source::qd:
      return s_->qd(sym.a);
    case Source::body:
      return body_quantity(*k_, sym.a, sym.b);
    case Source::variable:
      return variables_[static_cast<std::size_t>(sym.a)];
    case Source::constant:
      return sym.constant;
    default:
      return 0.0;  // refused by the law's scope when parsed
  }
}

bool LawEnvironment::differentiable(int symbol) const {
  switch (table_[symbol].source) {
    case Source::time:
    case Source::q:
    case Source::qd:
    case Source::body:
    case Source::variable:
    case Source::constant:
      return true;
    default:
      return false;
  }
}

void LawEnvironment::derivatives(int symbol, const runtime::KinematicsDerivatives& dk, int kk,
                                 double& d_dq, double& d_dqd) const {
  const Symbol& sym = table_[symbol];
  d_dq = sym.source == Source::q && sym.a == kk ? 1.0 : 0.0;
  d_dqd = sym.source == Source::qd && sym.a == kk ? 1.0 : 0.0;
  if (sym.source == Source::body) body_quantity_derivatives(*k_, dk, sym.a, sym.b, kk, d_dq, d_dqd);
}

}  // namespace symdyn::sim
