#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <symdyn/codegen/detail/derivation.hpp>
#include <symdyn/codegen/detail/dynamics_choice.hpp>
#include <symdyn/model/constraints.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/dynamics_derivatives.hpp>
#include <symdyn/model/trig_reduction.hpp>
#include <symdyn/symbolic/simplify.hpp>

namespace symdyn::codegen::detail {
namespace {

using model::Expr;

// Every dependent symbol (p, pd, pdd, their Jacobians, pdd at qdd = 0) and
// every intermediate is a definition of the programs: computed once, and
// only where an entry point needs it.
void define_dependents(const model::Kinematics& k, std::vector<symbolic::Definition>& definitions) {
  for (const auto& d : k.dependents) definitions.push_back({d.symbols.symbol, d.value});
  for (const auto& d : k.dependents) definitions.push_back({d.symbols.rate, d.rate});
  for (const auto& d : k.dependents)
    definitions.push_back({d.symbols.acceleration, d.acceleration});
  for (const auto& d : k.dependents) {
    for (std::size_t j = 0; j < d.jacobian.size(); ++j) {
      if (d.jacobian_symbols[j] != d.jacobian[j])
        definitions.push_back({d.jacobian_symbols[j], d.jacobian[j]});
    }
  }
  definitions.insert(definitions.end(), k.intermediates.begin(), k.intermediates.end());
}

// An array of these values under another name (dynamics_velocities' dw is
// partial_velocities' dw, named partial_velocities_dw), not one of `taken`.
std::vector<OutputArray>::iterator same_values(std::vector<OutputArray>& arrays,
                                               const std::vector<std::size_t>& taken,
                                               const std::vector<Expr>& values) {
  for (auto a = arrays.begin(); a != arrays.end(); ++a) {
    const auto index = static_cast<std::size_t>(a - arrays.begin());
    if (a->values == values && std::find(taken.begin(), taken.end(), index) == taken.end())
      return a;
  }
  return arrays.end();
}

// The header declares each output with its row's shape: its source must give as many values.
void check_sizes(const EntryPoint& e, const Sizes& sizes) {
  for (std::size_t i = 0; i < e.outputs.size(); ++i) {
    const std::size_t expected = shape_size(e.spec->outputs[i].shape, sizes);
    if (e.outputs[i].values.size() != expected) {
      throw std::logic_error(fmt::format("generate: {}'s {} has {} values, its shape {} {}",
                                         e.name(), e.outputs[i].name, e.outputs[i].values.size(),
                                         e.outputs[i].shape, expected));
    }
  }
}

// The distinct output arrays of the entry points with a program: the same
// name and values are one array (positions' R is velocities' R), written
// sparsely only if every output it is says so. Another array of a name
// already taken is renamed <entry>_<name> (relative_accelerations_R): the
// shared parts take each as a parameter.
void gather_arrays(Derivation& d, const Sizes& sizes) {
  for (const EntryPoint& e : d.entries) {
    std::vector<std::size_t>& mine = d.arrays_of.emplace_back();
    if (e.hand_written()) continue;
    check_sizes(e, sizes);
    for (const OutputArray& o : e.outputs) {
      const std::string renamed = fmt::format("{}_{}", e.name(), o.name);
      auto named = [&](const std::string& name) {
        return std::find_if(d.arrays.begin(), d.arrays.end(),
                            [&](const OutputArray& a) { return a.name == name; });
      };
      auto same = named(o.name);
      if (same != d.arrays.end() && same->values != o.values) same = named(renamed);
      if (same == d.arrays.end()) same = same_values(d.arrays, mine, o.values);
      if (same == d.arrays.end()) {
        const bool taken = named(o.name) != d.arrays.end();
        same = d.arrays.insert(d.arrays.end(),
                               {taken ? renamed : o.name, o.shape, o.values, o.sparse});
      }
      same->sparse = same->sparse && o.sparse;
      mine.push_back(static_cast<std::size_t>(same - d.arrays.begin()));
    }
  }
}

// Fewer operations, then a lower weighted cost (divisions, calls), or as many.
bool no_longer(const symbolic::Program& a, const symbolic::Program& b) {
  const symbolic::OperationCount x = a.operation_count(), y = b.operation_count();
  return std::pair(x.total(), x.weighted()) <= std::pair(y.total(), y.weighted());
}

// Each entry point of `other` (the plain derivation) no longer than chosen's replaces it.
void keep_shorter_entries(Derivation& chosen, Derivation&& other) {
  for (std::size_t i = 0; i < chosen.entries.size(); ++i) {
    auto& mine = chosen.whole[i];
    auto& theirs = other.whole[i];
    if (mine && theirs && no_longer(*theirs, *mine)) {
      chosen.entries[i] = std::move(other.entries[i]);
      mine = std::move(theirs);
    }
  }
}

// What the program prints as statements: its outputs and every computing
// instruction (loads print inline).
std::size_t statements(const symbolic::Program& program) {
  std::size_t n = program.output_count();
  for (const symbolic::Instruction& i : program.instructions()) {
    n += i.op != symbolic::Opcode::Const && i.op != symbolic::Opcode::Input;
  }
  return n;
}

// The statements of the entry points on the hot path (not EntryPointSpec::cold).
std::size_t hot_statements(const Derivation& d, const std::vector<std::size_t>& all_inputs) {
  const std::vector<std::vector<std::size_t>> groups = entry_outputs(d);
  std::vector<std::size_t> hot;
  bool any_cold = false;
  for (std::size_t e = 0, g = 0; e < d.entries.size(); ++e) {
    if (d.entries[e].hand_written()) continue;
    const std::vector<std::size_t>& outputs = groups[g++];
    if (d.entries[e].spec->cold) {
      any_cold = true;
      continue;
    }
    hot.insert(hot.end(), outputs.begin(), outputs.end());
  }
  if (!any_cold) return statements(d.program);
  std::sort(hot.begin(), hot.end());
  hot.erase(std::unique(hot.begin(), hot.end()), hot.end());
  return statements(d.program.subprogram(hot, all_inputs));
}

}  // namespace

std::vector<std::vector<std::size_t>> entry_outputs(const Derivation& d) {
  std::vector<std::size_t> first_output;  // of each array
  std::size_t next = 0;
  for (const OutputArray& a : d.arrays) {
    first_output.push_back(next);
    next += a.values.size();
  }
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t e = 0; e < d.entries.size(); ++e) {
    if (d.entries[e].hand_written()) continue;
    std::vector<std::size_t>& outputs = groups.emplace_back();
    for (std::size_t a : d.arrays_of[e]) {
      for (std::size_t i = 0; i < d.arrays[a].values.size(); ++i)
        outputs.push_back(first_output[a] + i);
    }
  }
  return groups;
}

Deriver::Deriver(const model::Model& model, const Options& options, const Selection& selection,
                 const InputSymbols& inputs)
    : model_(model),
      options_(options),
      selection_(selection),
      inputs_(inputs),
      sizes_{.nq = model.coordinates().size(),
             .nbody = model.bodies().size(),
             .ndep = model.dependents().size(),
             .nind = model.num_independent(),
             .ncon = model.num_implicit()} {}

Derivation Deriver::run() {
  // Node ids break ties in scheduling and pair CSE, and the simplifier makes
  // nodes of its own (its rules' constants, the forms it tries): the plain
  // kinematics are made first, as without simplification, so that what it
  // leaves alone compiles to the same code as without it (not the
  // equations of motion: long to derive without simplification). The plain
  // derivation below starts from them.
  if (options_.simplify) plain_kinematics_ = model::derive_kinematics(model_, derive_options());
  Derivation chosen = derive(options_.simplify);
  // Simplification works expression by expression; common subexpressions
  // are found later, across them. A form that is shorter alone may share
  // less, so the code keeps the shorter of the two: entry point by entry
  // point where each is its own program, the whole program where they
  // share it. Where simplification changed no expression, the plain
  // derivation is the same expressions (the derivation is deterministic and
  // otherwise the same), hence the same programs: nothing to compare.
  // At equal length the plain form stays: another form of as many
  // operations gains nothing and may compile to more instructions.
  if (options_.simplify && chosen.simplified) {
    Derivation plain = derive(false);
    if (!chosen.whole.empty() && !plain.whole.empty()) {
      keep_shorter_entries(chosen, std::move(plain));
    } else if (no_longer(plain.program, chosen.program)) {
      chosen = std::move(plain);
    }
  }
  return chosen;
}

// The derivation's options, without simplification unless one is given.
model::DeriveOptions Deriver::derive_options(model::SimplifyFunction simplify) const {
  model::DeriveOptions options;
  options.simplify = std::move(simplify);
  options.symbolic_partials = options_.symbolic_partials;
  options.relative_only = !selection_.needs_absolute_motion();
  return options;
}

Derivation Deriver::derive(bool simplify) {
  std::optional<symbolic::Simplifier> simplifier;  // its rule tables take time to build
  Derivation d;
  model::SimplifyFunction simplify_function;
  if (simplify) {
    simplifier.emplace();
    simplify_function = [&simplifier, &d](Expr e) {
      const Expr s = (*simplifier)(e);
      d.simplified = d.simplified || s != e;
      return s;
    };
  }
  const model::DeriveOptions derive = derive_options(simplify_function);
  const model::Kinematics k = !simplify && plain_kinematics_
                                  ? *plain_kinematics_
                                  : model::derive_kinematics(model_, derive);
  define_dependents(k, d.definitions);
  std::optional<model::Dynamics> dynamics;
  if (options_.equations_of_motion && selection_.needs_equations_of_motion()) {
    dynamics = model::derive_dynamics(model_, k, derive.simplify,
                                      selection_.needs_reactions(options_.joint_reactions));
    if (derive.simplify) model::reduce_trigonometry(*dynamics, k);
    d.definitions.insert(d.definitions.end(), dynamics->definitions.begin(),
                         dynamics->definitions.end());
  }
  std::optional<DynamicsDerivatives> derivatives;
  if (const Derivatives level = selection_.needs_derivatives(options_.derivatives);
      dynamics && level != Derivatives::none) {
    derivatives = derive_derivatives(*dynamics, k, level == Derivatives::all, d.definitions);
    d.definitions.insert(d.definitions.end(), derivatives->definitions.begin(),
                         derivatives->definitions.end());
    if (derivatives_reason_.empty())
      derivatives_reason_ = derivatives->reason;  // the first derivation's, as choice_
  }
  std::optional<model::Constraints> constraints;
  if (!model_.loops().empty()) constraints = model::derive_constraints(model_, k, derive.simplify);
  std::optional<ConstraintDerivatives> constraint_derivatives;
  if (constraints && derivatives) {
    constraint_derivatives =
        derive_constraint_derivatives(*constraints, inputs_[Input::q], inputs_[Input::qd],
                                      inputs_[Input::qdd], inputs_[Input::mu], d.definitions);
    d.definitions.insert(d.definitions.end(), constraint_derivatives->definitions.begin(),
                         constraint_derivatives->definitions.end());
  }
  d.entries = build_entry_points({model_, k, dynamics ? &*dynamics : nullptr,
                                  derivatives ? &*derivatives : nullptr,
                                  constraints ? &*constraints : nullptr,
                                  constraint_derivatives ? &*constraint_derivatives : nullptr});
  const DynamicsWays ways{.method = options_.dynamics,
                          .nq = sizes_.nq,
                          .why_not = dynamics ? dynamics->why_not : std::string(),
                          .operations = [&](const EntryPoint& e) {
                            return compile(e, d.definitions)->operation_count().total();
                          }};
  choose_dynamics(d.entries, choice_, ways);
  selection_.apply(d.entries, choice_);
  compile_programs(d);
  return d;
}

// The program of every output array, and where the code is short enough
// to print each entry point whole (or asked to), each one's own.
void Deriver::compile_programs(Derivation& d) const {
  gather_arrays(d, sizes_);
  std::vector<Expr> outputs;
  for (const OutputArray& a : d.arrays)
    outputs.insert(outputs.end(), a.values.begin(), a.values.end());
  d.program = symbolic::compile_program(inputs_.all(), outputs, d.definitions, entry_outputs(d));
  const std::vector<Input> every_input(std::begin(kInputs), std::end(kInputs));
  if (options_.part_instructions == 0 ||
      hot_statements(d, inputs_.indices(every_input)) <= options_.split_above) {
    for (std::size_t e = 0; e < d.entries.size(); ++e) d.whole.push_back(whole_program(d, e));
  }
}

// The catalogue's entry points that these options and this derivation give
// (the recursive dynamics where it applies, choose_dynamics chooses later).
std::vector<EntryPoint> Deriver::build_entry_points(const Quantities& quantities) const {
  std::vector<EntryPoint> entries;
  for (const EntryPointSpec& spec : catalogue()) {
    if (derivable(spec.needs, quantities))
      entries.push_back(build_entry_point(spec, quantities, sizes_));
  }
  return entries;
}

bool Deriver::derivable(const Needs& needs, const Quantities& quantities) const {
  const model::Dynamics* dynamics = quantities.dynamics;
  const bool partials = needs.partials == Partials::either ||
                        (needs.partials == Partials::symbolic) == options_.symbolic_partials;
  const bool recursive =
      dynamics && !dynamics->forward.empty() && options_.dynamics != DynamicsMethod::mass_matrix;
  return partials && (!needs.equations_of_motion || dynamics) &&
         (!needs.reactions || (dynamics && !dynamics->reactions.empty())) &&
         (!needs.loops || quantities.constraints) && (!needs.recursive_dynamics || recursive) &&
         (!needs.loops || needs.derivatives == Derivatives::none ||
          quantities.constraint_derivatives) &&
         (needs.derivatives == Derivatives::none ||
          (quantities.derivatives &&
           (needs.derivatives == Derivatives::dynamics || quantities.derivatives->kinematics)));
}

// dtau/dq and dtau/dqd, each form of tau weighed by its own program's operations.
DynamicsDerivatives Deriver::derive_derivatives(
    const model::Dynamics& dynamics, const model::Kinematics& kinematics, bool with_kinematics,
    const std::vector<symbolic::Definition>& definitions) const {
  const std::vector<Input> inputs{Input::t, Input::q, Input::qd, Input::qdd, Input::param};
  const OperationCounter operations = [&](const std::vector<Expr>& outputs,
                                          const std::vector<symbolic::Definition>& defined) {
    return symbolic::compile_program(inputs_.of(inputs), outputs, defined)
        .operation_count()
        .total();
  };
  return derive_dynamics_derivatives(
      dynamics, model::derive_inverse_dynamics_derivatives(model_, kinematics),
      with_kinematics ? &kinematics : nullptr, inputs_[Input::q], inputs_[Input::qd],
      inputs_[Input::qdd], definitions, operations);
}

// The entry point's own program, or nothing for a hand-written body.
std::optional<symbolic::Program> Deriver::compile(
    const EntryPoint& e, const std::vector<symbolic::Definition>& definitions) const {
  if (e.hand_written()) return std::nullopt;
  std::vector<Expr> outputs;
  for (const OutputArray& o : e.outputs)
    outputs.insert(outputs.end(), o.values.begin(), o.values.end());
  return symbolic::compile_program(inputs_.of(e.spec->inputs), outputs, definitions);
}

// Entry point e's own program: the derivation's whole program where e is its
// only entry point with a program (generate --only), else compiled alone.
std::optional<symbolic::Program> Deriver::whole_program(const Derivation& d, std::size_t e) const {
  std::vector<std::size_t> every_array(d.arrays.size());
  std::iota(every_array.begin(), every_array.end(), std::size_t{0});
  if (d.entries[e].hand_written() || d.arrays_of[e] != every_array)
    return compile(d.entries[e], d.definitions);
  std::vector<std::size_t> outputs(d.program.output_count());
  std::iota(outputs.begin(), outputs.end(), std::size_t{0});
  return d.program.subprogram(outputs, inputs_.indices(d.entries[e].spec->inputs));
}

}  // namespace symdyn::codegen::detail
