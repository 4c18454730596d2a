#pragma once
// The names a scenario's expressions read, resolved once against the model:
//   t; each coordinate q by name, its rate <q>_dot and acceleration <q>_ddot;
//   <body>.x .y .z (G, global), .vx .vy .vz (velocity of G), .wx .wy .wz
//   (angular velocity), .ux .uy .uz (velocity of G in body axes), .R00 ..
//   .R22 (rotation matrix, body to global);
//   kinetic_energy, gravitational_energy, elastic_energy, total_energy,
//   momentum_x .. _z, angular_momentum_x .. _z (about the global origin);
//   reaction.<body>.Fx .. .Mz, the body's joint reaction (body axes, about
//   its joint point: runtime::MultibodySystem::joint_reactions);
//   reaction.<loop>.Fx .. (or .lambda<j>), a closed loop's reaction
//   (runtime::MultibodySystem::loop_reactions);
// with closed loops the coordinates are the tree's (q, then the implicit
// dependent parameters p): the state holds q, p and its rates are solved.
//   <element>.<quantity> of a force element (elements.hpp lists them);
//   the scenario's variables; rtol, atol, t_end.
// Which of them an expression may read depends on where it is (a force law
// sees the state and the kinematics, a check only statistics): a Scope says.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "expression.hpp"
#include <symdyn/runtime/force_element.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::sim {

enum class Source {
  time,
  q,
  qd,
  qdd,
  body,
  energy,
  momentum,
  reaction,
  loop_reaction,
  element,
  variable,
  constant,
  statistic
};

struct Symbol {
  Source source = Source::time;
  int a = 0, b = 0;  // coordinate; body and attribute; element and quantity; variable; statistic
  double constant = 0.0;
  bool operator==(const Symbol&) const = default;
};

// A force element of a scenario: switched on and off by events, and the
// quantities it reports (named, each a function of the kinematics).
class ScenarioElement : public runtime::ForceElement {
 public:
  using Quantity = std::function<double(const runtime::State& s, const runtime::Kinematics& k)>;
  ScenarioElement(std::string name, std::shared_ptr<const runtime::ForceElement> inner,
                  bool enabled);

  std::string name() const override { return inner_->name(); }
  runtime::KinematicsLevel reads() const override { return inner_->reads(); }
  void apply(const runtime::State& s, const runtime::Kinematics& k,
             runtime::Loads& loads) const override;
  // The inner element's exact derivatives where it has them (none while switched off).
  runtime::LoadDerivatives load_derivatives() const override { return inner_->load_derivatives(); }
  void add_load_derivatives(const runtime::State& s, const runtime::Kinematics& k,
                            const runtime::KinematicsDerivatives& dk, runtime::Matrix& dQ_dq,
                            runtime::Matrix& dQ_dqd) const override;
  double potential_energy(const runtime::State& s, const runtime::Kinematics& k) const override;

  const std::string& id() const { return id_; }
  bool enabled() const { return enabled_; }
  void enable(bool on) { enabled_ = on; }
  void add_quantity(std::string name, Quantity q);
  const std::vector<std::string>& quantity_names() const { return quantity_names_; }
  // 0 while switched off.
  double quantity(int which, const runtime::State& s, const runtime::Kinematics& k) const;
  const runtime::ForceElement& inner() const { return *inner_; }

 private:
  std::string id_;
  std::shared_ptr<const runtime::ForceElement> inner_;
  bool enabled_;
  std::vector<std::string> quantity_names_;
  std::vector<Quantity> quantities_;
};

// Every symbol of a run, each once.
class SymbolTable {
 public:
  int add(const Symbol& s);
  const Symbol& operator[](int i) const { return symbols_[static_cast<std::size_t>(i)]; }
  std::size_t size() const { return symbols_.size(); }

 private:
  std::vector<Symbol> symbols_;
};

// What the names of one kind of expression may be.
struct Scope {
  bool time = true;            // t
  bool state = true;           // q, qd and body quantities
  bool accelerations = false;  // qdd
  bool system = false;         // energies, momentum, element quantities
  bool run_constants = false;  // rtol, atol, t_end
};

// The names of a run: the model's, the elements', the variables'.
struct Names {
  const runtime::Model* model = nullptr;
  const std::vector<std::shared_ptr<ScenarioElement>>* elements = nullptr;
  std::vector<std::string> variables;
  double rtol = 0.0, atol = 0.0, t_end = 0.0;
};

// name -> symbol in `table`, ExpressionError listing the valid names.
int resolve_name(std::string_view name, const Names& names, const Scope& scope, SymbolTable& table);
Resolver make_resolver(const Names& names, const Scope& scope, SymbolTable& table);

// The values at one output instant: what the state gives directly, and the
// kinematics, energies and momentum computed once per instant when read.
class SampleEnvironment : public Environment {
 public:
  SampleEnvironment(runtime::MultibodySystem& system, const SymbolTable& table,
                    const std::vector<std::shared_ptr<ScenarioElement>>& elements,
                    const std::vector<double>& variables, const std::vector<double>& statistics);
  void set(const runtime::State& s, const runtime::Vector& qdd);
  double value(int symbol) const override;

 private:
  const runtime::Kinematics& kinematics() const;

  runtime::MultibodySystem& system_;
  const SymbolTable& table_;
  const std::vector<std::shared_ptr<ScenarioElement>>& elements_;
  const std::vector<double>& variables_;
  const std::vector<double>& statistics_;
  const runtime::State* s_ = nullptr;
  const runtime::Vector* qdd_ = nullptr;
  mutable bool have_kinematics_ = false, have_energies_ = false, have_momentum_ = false,
               have_reactions_ = false, have_loop_reactions_ = false;
  mutable runtime::Energies energies_;
  mutable runtime::Momentum momentum_;
  mutable runtime::Matrix reactions_;       // (6 x nbody)
  mutable runtime::Vector loop_reactions_;  // (ncon)
  // Closed loops: the tree's state and accelerations (q, p) at this instant.
  mutable bool have_extended_ = false;
  mutable runtime::State extended_;
  mutable runtime::Vector xdd_;
  // The state force elements see: with closed loops the tree's, x = (q, p).
  const runtime::State& tree_state() const;
  // A coordinate's value (0), rate (1) or acceleration (2), p's from the tree's.
  double coordinate(int j, int order) const;
};

// Body quantity `attribute` (the order of the list in quantities.cpp) of body i.
double body_quantity(const runtime::Kinematics& k, int body, int attribute);
// Its derivatives with respect to q_kk and qd_kk, from the kinematics k and their
// derivatives dk at the same state (runtime/kinematics_derivatives.hpp).
void body_quantity_derivatives(const runtime::Kinematics& k,
                               const runtime::KinematicsDerivatives& dk, int body, int attribute,
                               int kk, double& d_dq, double& d_dqd);

// The values a force law reads: the state and the kinematics it is given.
class LawEnvironment : public Environment {
 public:
  LawEnvironment(const SymbolTable& table, const std::vector<double>& variables)
      : table_(table), variables_(variables) {}
  void set(const runtime::State& s, const runtime::Kinematics& k) {
    s_ = &s;
    k_ = &k;
  }
  double value(int symbol) const override;
  // Whether a symbol's derivatives with respect to q and qd are known: those of
  // the state, the bodies' kinematics, time, variables and constants.
  bool differentiable(int symbol) const;
  // A differentiable symbol's ∂/∂q_kk and ∂/∂qd_kk at the state and kinematics
  // set, dk their derivatives (read for body quantities alone).
  void derivatives(int symbol, const runtime::KinematicsDerivatives& dk, int kk, double& d_dq,
                   double& d_dqd) const;

 private:
  const SymbolTable& table_;
  const std::vector<double>& variables_;
  const runtime::State* s_ = nullptr;
  const runtime::Kinematics* k_ = nullptr;
};

}  // namespace symdyn::sim
