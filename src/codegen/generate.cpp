#include <symdyn/codegen/generate.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <symdyn/model/diagnostics.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/identifier.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/model/trig_reduction.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/print.hpp>
#include <symdyn/symbolic/simplify.hpp>

namespace symdyn::codegen {
namespace {

using model::Expr;
using model::ModelError;

// An output array of an entry point: name, shape comment, one expression per entry.
struct OutputArray {
  std::string name;
  std::string shape;
  std::vector<Expr> values;
};

// An entry point as data: its input arrays (by name), its output arrays, its doc.
struct EntryPoint {
  std::string name;
  std::string doc;
  std::vector<std::string> inputs;  // among "t", "q", "qd", "qdd", "tau", "param"
  std::vector<OutputArray> outputs;
  std::string body;  // a hand-written body instead of a program (numeric partials, forward_dynamics)
};

// forward_dynamics returns its pivot check; every other entry point nothing.
std::string return_type(const EntryPoint& e) { return e.name == "forward_dynamics" ? "int" : "void"; }

// What the header says of a hand-written body instead of its operation count.
std::string hand_written_note(const std::string& name) {
  return name == "forward_dynamics" ? "(forward_dynamics_pivots and the pivot check)" : "(loops over velocities)";
}

// One field of every body's absolute (or, with `relative`, relative) motion, flattened.
template <class Field>
std::vector<Expr> flatten(const std::vector<model::BodyKinematics>& bodies, Field field, bool relative = false) {
  std::vector<Expr> out;
  for (const auto& b : bodies) {
    const auto& v = relative ? b.relative.*field : b.*field;
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

// dv/dqd or dw/dqd of every body: (nbody x nq x 3).
std::vector<Expr> flatten_partials(const std::vector<model::BodyKinematics>& bodies,
                                   std::vector<model::Vec3> model::Motion::*field, bool relative = false) {
  std::vector<Expr> out;
  for (const auto& b : bodies) {
    const auto& partials = relative ? b.relative.*field : b.*field;
    for (const model::Vec3& v : partials) out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

std::string array_literal(const std::vector<double>& values) {
  std::vector<std::string> parts;
  for (double v : values) parts.push_back(symbolic::cpp_literal(v));
  if (parts.empty()) parts.push_back("0.0");
  return fmt::format("{{{}}}", fmt::join(parts, ", "));
}

std::string string_array_literal(const std::vector<std::string>& values) {
  std::vector<std::string> parts;
  for (const auto& v : values) parts.push_back(fmt::format("\"{}\"", v));
  if (parts.empty()) parts.push_back("nullptr");
  return fmt::format("{{{}}}", fmt::join(parts, ", "));
}

std::size_t at_least_one(std::size_t n) { return n > 0 ? n : 1; }

// "name[i]", without a format string: an entry point names thousands of elements.
std::string element(const std::string& name, std::size_t i) {
  std::string out = name;
  out += '[';
  out += std::to_string(i);
  out += ']';
  return out;
}

// The C++ text of element i of an input array; the time t is a scalar.
std::string input_element(const std::string& in, std::size_t i) { return in == "t" ? "t" : element(in, i); }

// The inputs of every entry point are among these arrays, in this order.
constexpr const char* kInputs[] = {"t", "q", "qd", "qdd", "tau", "param"};

// The entry points of the equations of motion: derived only when one is emitted.
constexpr const char* kDynamicsEntryPoints[] = {"mass_matrix",         "bias_forces",      "dynamics",
                                                "dynamics_positions",  "dynamics_velocities", "inverse_dynamics",
                                                "forward_dynamics_pivots", "forward_dynamics"};

// The entry points computed from each body's motion relative to its reference
// alone: when only these are emitted, no absolute motion is composed.
constexpr const char* kRelativeEntryPoints[] = {"inertia", "relative_accelerations", "relative_partial_velocities",
                                                "relative_accelerations_partials", "dependent_parameters"};

// Hand-written bodies call another entry point, emitted with them.
constexpr std::pair<const char*, const char*> kBodyCalls[] = {{"forward_dynamics", "forward_dynamics_pivots"},
                                                              {"partial_velocities", "velocities"}};

// Below this share of its diagonal entry of D a pivot of the articulated-body
// algorithm is rounding: the runtime's SpdSolver::kSingularRatio (64 ulps).
constexpr double kSingularPivotRatio = 64 * 2.220446049250313e-16;

class Emitter {
 public:
  // `sequences` come from the model as written: sharing motions makes some relative.
  Emitter(const model::Model& model, std::vector<model::AngleSequence> sequences, std::string_view variant,
          std::string_view basename, const Options& options)
      : model_(model),
        variant_(variant),
        basename_(basename),
        options_(options),
        checks_(model::domain_checks(model)),
        sequences_(std::move(sequences)) {
    struct_name_ = std::string(basename);
    for (const char* in : kInputs) symbols_[in];
    const auto& coords = model.coordinates();
    for (const auto& c : coords) {
      symbols_["q"].push_back(c.q);
      symbols_["qd"].push_back(c.qd);
      symbols_["qdd"].push_back(c.qdd);
    }
    symbols_["t"] = {model.time()};
    symbols_["tau"] = model::generalized_force_symbols(model);
    for (const auto& p : model.parameters()) symbols_["param"].push_back(p.symbol);
  }

  GeneratedCode run() {
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
    entries_ = std::move(chosen.entries);
    GeneratedCode code;
    code.struct_name = struct_name_;
    code.dynamics = choice_.value_or(DynamicsChoice{});
    // The source is appended to, piece after piece: it is most of the
    // output, and formatting it through fmt would copy it again.
    code.source = fmt::format("// Generated by symdyn from model '{}', variant '{}'. Do not edit.\n"
                              "#include \"{}.hpp\"\n\n#include <cmath>\n\nnamespace {} {{\n",
                              model_.name(), variant_, basename_, options_.name_space);
    if (chosen.whole.empty()) {
      emit_shared(chosen, code);
    } else {
      for (std::size_t i = 0; i < entries_.size(); ++i) {
        EmittedFunction& f = emitted(entries_[i], code.functions);
        if (entries_[i].body.empty()) f.program = std::move(chosen.whole[i]);
        code.source += function_text(entries_[i], f.program ? symbolic::emit_cpp(*f.program, naming(entries_[i]))
                                                            : entries_[i].body);
        if (f.program) f.operations = f.program->operation_count();
      }
    }
    code.source += domain_arguments_text();
    // The guard's name depends on everything emitted, so it is computed last.
    const std::string header = emit_header(code.functions);
    const std::string closing = fmt::format("}}  // namespace {}\n", options_.name_space);
    const std::string unique =
        fmt::format("symdyn_model_{}_{:016x}", struct_name_, text_hash(code.source + header + closing));
    code.source += link_guard_definitions(unique);
    code.source += '\n' + closing;
    code.header = header + link_guard_reference(unique) + closing;
    return code;
  }

 private:
  // The entry points of one derivation and the program computing all their
  // outputs (those of entry points with a hand-written body aside), each
  // distinct output array once. A short program is printed as one function
  // per entry point, each its own program (`whole`, by entry point; absent
  // for a hand-written body); a longer one as parts shared between the entry
  // points (emit_cpp_shared).
  struct Derivation {
    std::vector<EntryPoint> entries;
    std::vector<OutputArray> arrays;  // distinct output arrays, with names unique among them
    std::vector<std::vector<std::size_t>> arrays_of;  // (entries) its arrays, indices into `arrays`
    symbolic::Program program;
    std::vector<std::optional<symbolic::Program>> whole;  // empty: shared
    bool simplified = false;  // simplification changed some expression
  };

  // The derivation's options, without simplification unless one is given.
  model::DeriveOptions derive_options(model::SimplifyFunction simplify = {}) const {
    model::DeriveOptions options;
    options.simplify = std::move(simplify);
    options.symbolic_partials = options_.symbolic_partials;
    options.relative_only = !wants_absolute_motion();
    return options;
  }

  Derivation derive(bool simplify) {
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
    const model::Kinematics k = !simplify && plain_kinematics_ ? *plain_kinematics_ : model::derive_kinematics(model_, derive);
    definitions_.clear();
    define_dependents(k);
    d.entries = build_entry_points(k, derive.simplify);
    choose_dynamics(d.entries);
    select_entry_points(d.entries);
    gather_arrays(d);
    std::vector<Expr> outputs;
    for (const OutputArray& a : d.arrays) outputs.insert(outputs.end(), a.values.begin(), a.values.end());
    d.program = symbolic::compile_program(all_inputs(), outputs, definitions_, entry_outputs(d.entries, d));
    std::size_t statements = d.program.output_count();
    for (const symbolic::Instruction& i : d.program.instructions()) {
      statements += i.op != symbolic::Opcode::Const && i.op != symbolic::Opcode::Input;
    }
    if (options_.part_instructions == 0 || statements <= options_.split_above) {
      for (std::size_t e = 0; e < d.entries.size(); ++e) d.whole.push_back(whole_program(d, e));
    }
    return d;
  }

  // Entry point e's own program: the derivation's whole program where e is its
  // only entry point with a program (generate --only), else compiled alone.
  std::optional<symbolic::Program> whole_program(const Derivation& d, std::size_t e) const {
    std::vector<std::size_t> every_array(d.arrays.size());
    std::iota(every_array.begin(), every_array.end(), std::size_t{0});
    if (!d.entries[e].body.empty() || d.arrays_of[e] != every_array) return compile(d.entries[e]);
    std::vector<std::size_t> outputs(d.program.output_count());
    std::iota(outputs.begin(), outputs.end(), std::size_t{0});
    return d.program.subprogram(outputs, input_indices(d.entries[e]));
  }

  // The outputs (indices among the program's) of each entry point with a
  // program, in order: what each runs of the shared program.
  static std::vector<std::vector<std::size_t>> entry_outputs(const std::vector<EntryPoint>& entries,
                                                             const Derivation& d) {
    std::vector<std::size_t> first_output;  // of each array
    std::size_t next = 0;
    for (const OutputArray& a : d.arrays) {
      first_output.push_back(next);
      next += a.values.size();
    }
    std::vector<std::vector<std::size_t>> groups;
    for (std::size_t e = 0; e < entries.size(); ++e) {
      if (!entries[e].body.empty()) continue;
      std::vector<std::size_t>& outputs = groups.emplace_back();
      for (std::size_t a : d.arrays_of[e]) {
        for (std::size_t i = 0; i < d.arrays[a].values.size(); ++i) outputs.push_back(first_output[a] + i);
      }
    }
    return groups;
  }

  // Fewer operations, then a lower weighted cost (divisions, calls), or as many.
  static bool no_longer(const symbolic::Program& a, const symbolic::Program& b) {
    const symbolic::OperationCount x = a.operation_count(), y = b.operation_count();
    return std::pair(x.total(), x.weighted()) <= std::pair(y.total(), y.weighted());
  }

  // Each entry point of `other` (the plain derivation) no longer than chosen's replaces it.
  static void keep_shorter_entries(Derivation& chosen, Derivation&& other) {
    for (std::size_t i = 0; i < chosen.entries.size(); ++i) {
      auto& mine = chosen.whole[i];
      auto& theirs = other.whole[i];
      if (mine && theirs && no_longer(*theirs, *mine)) {
        chosen.entries[i] = std::move(other.entries[i]);
        mine = std::move(theirs);
      }
    }
  }

  // The distinct output arrays of the entry points with a program: the same
  // name and values are one array (positions' R is velocities' R). Another
  // array of a name already taken is renamed <entry>_<name>
  // (relative_accelerations_R): the shared parts take each as a parameter.
  static void gather_arrays(Derivation& d) {
    for (const EntryPoint& e : d.entries) {
      std::vector<std::size_t>& mine = d.arrays_of.emplace_back();
      if (!e.body.empty()) continue;
      for (const OutputArray& o : e.outputs) {
        const std::string renamed = e.name + "_" + o.name;
        auto named = [&](const std::string& name) {
          return std::find_if(d.arrays.begin(), d.arrays.end(), [&](const OutputArray& a) { return a.name == name; });
        };
        auto same = named(o.name);
        if (same != d.arrays.end() && same->values != o.values) same = named(renamed);
        if (same == d.arrays.end()) same = same_values(d.arrays, mine, o.values);
        if (same == d.arrays.end()) {
          const bool taken = named(o.name) != d.arrays.end();
          same = d.arrays.insert(d.arrays.end(), {taken ? renamed : o.name, o.shape, o.values});
        }
        mine.push_back(static_cast<std::size_t>(same - d.arrays.begin()));
      }
    }
  }

  // An array of these values under another name (dynamics_velocities' dw is
  // partial_velocities' dw, named partial_velocities_dw), not one of `taken`.
  static std::vector<OutputArray>::iterator same_values(std::vector<OutputArray>& arrays,
                                                        const std::vector<std::size_t>& taken,
                                                        const std::vector<Expr>& values) {
    for (auto a = arrays.begin(); a != arrays.end(); ++a) {
      const auto index = static_cast<std::size_t>(a - arrays.begin());
      if (a->values == values && std::find(taken.begin(), taken.end(), index) == taken.end()) return a;
    }
    return arrays.end();
  }

  std::vector<Expr> all_inputs() const {
    std::vector<Expr> inputs;
    for (const char* in : kInputs) inputs.insert(inputs.end(), symbols_.at(in).begin(), symbols_.at(in).end());
    return inputs;
  }

  EmittedFunction& emitted(const EntryPoint& e, std::vector<EmittedFunction>& functions) const {
    EmittedFunction& f = functions.emplace_back();
    f.name = e.name;
    f.inputs = e.inputs;
    for (const OutputArray& o : e.outputs) f.outputs.emplace_back(o.name, o.values.size());
    return f;
  }

  // Every entry point with a program runs the parts its outputs need, the
  // parts first (internal functions), then the entry points in order.
  void emit_shared(const Derivation& d, GeneratedCode& code) const {
    symbolic::CppNaming naming;
    for (const char* in : kInputs) {
      const std::size_t n = symbols_.at(in).size();
      naming.input_arrays.emplace_back(in, n);
      for (std::size_t i = 0; i < n; ++i) naming.inputs.push_back(input_element(in, i));
    }
    for (const OutputArray& a : d.arrays) {
      for (std::size_t i = 0; i < a.values.size(); ++i) naming.outputs.push_back(element(a.name, i));
      naming.output_arrays.emplace_back(a.name, a.values.size());
    }
    // The outputs of each entry point with a program.
    const std::vector<std::vector<std::size_t>> functions = entry_outputs(entries_, d);
    std::vector<std::size_t> function_of(entries_.size(), entries_.size());
    for (std::size_t e = 0, f = 0; e < entries_.size(); ++e) {
      if (entries_[e].body.empty()) function_of[e] = f++;
    }
    const symbolic::CppShared shared = symbolic::emit_cpp_shared(d.program, naming, functions, options_.part_instructions);
    code.source += emit_part_functions(shared, naming);
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      const EntryPoint& entry = entries_[e];
      EmittedFunction& f = emitted(entry, code.functions);
      if (function_of[e] == entries_.size()) {
        code.source += function_text(entry, entry.body);
        continue;
      }
      const std::size_t fn = function_of[e];
      f.program = d.program.subprogram(functions[fn], input_indices(entry));
      f.operations = f.program->operation_count();
      code.source += function_text(entry, part_calls(e, d, shared.parts, shared.functions[fn], naming));
    }
  }

  // The indices of the entry point's inputs among all_inputs().
  std::vector<std::size_t> input_indices(const EntryPoint& e) const {
    std::vector<std::size_t> indices;
    std::size_t first = 0;
    for (const char* in : kInputs) {
      const std::size_t n = symbols_.at(in).size();
      if (std::find(e.inputs.begin(), e.inputs.end(), in) != e.inputs.end()) {
        for (std::size_t i = 0; i < n; ++i) indices.push_back(first + i);
      }
      first += n;
    }
    return indices;
  }

  // The parts as internal functions. noinline keeps the compiler from gluing
  // them back into one function; __restrict on every array (outputs never
  // overlap inputs, nor each other) tells it that a store changes no input,
  // output or scratch entry it has read, so nothing is read again and its
  // alias queries end at once.
  std::string emit_part_functions(const symbolic::CppShared& shared, const symbolic::CppNaming& naming) const {
    std::vector<std::string> names;  // of the entry points with a program, by function
    for (const EntryPoint& e : entries_) {
      if (e.body.empty()) names.push_back(e.name);
    }
    std::string out = "\nnamespace {\n";
    for (std::size_t p = 0; p < shared.parts.size(); ++p) {
      const symbolic::CppPart& part = shared.parts[p];
      std::vector<std::string> params, users;
      for (std::size_t a : part.input_arrays) {
        const std::string& in = naming.input_arrays[a].first;
        params.push_back(in == "t" ? "double t" : fmt::format("const double* __restrict {}", in));
      }
      for (std::size_t a : part.output_arrays) params.push_back(fmt::format("double* __restrict {}", naming.output_arrays[a].first));
      if (part.scratch) params.push_back(fmt::format("double* __restrict {}", naming.scratch));
      for (std::size_t f : part.functions) users.push_back(names[f]);
      out += fmt::format("\n// Part {} of {}, run by {}.\n[[gnu::noinline]] void part{}({}) {{\n", p + 1,
                         shared.parts.size(), fmt::join(users, ", "), p, fmt::join(params, ", "));
      out += part.body;
      out += "}\n";
    }
    out += "\n}  // namespace\n";
    return out;
  }

  // An entry point's body: its scratch array, then a call of each of its parts.
  std::string part_calls(std::size_t entry, const Derivation& d, const std::vector<symbolic::CppPart>& parts,
                         const symbolic::CppFunctionParts& mine, const symbolic::CppNaming& naming) const {
    const EntryPoint& e = entries_[entry];
    std::string out;
    if (mine.scratch_size > 0) out += fmt::format("  double {}[{}];\n", naming.scratch, mine.scratch_size);
    for (std::size_t p : mine.parts) {
      const symbolic::CppPart& part = parts[p];
      std::vector<std::string> args;
      for (std::size_t a : part.input_arrays) {
        const std::string& in = naming.input_arrays[a].first;
        if (std::find(e.inputs.begin(), e.inputs.end(), in) == e.inputs.end()) {
          throw std::logic_error(fmt::format("generate: {} needs input {}, which it does not take", e.name, in));
        }
        args.push_back(in);
      }
      for (std::size_t a : part.output_arrays) {
        const auto& arrays = d.arrays_of[entry];
        const auto it = std::find(arrays.begin(), arrays.end(), a);
        args.push_back(e.outputs[static_cast<std::size_t>(it - arrays.begin())].name);
      }
      if (part.scratch) args.push_back(naming.scratch);
      out += fmt::format("  part{}({});\n", p, fmt::join(args, ", "));
    }
    return out;
  }

  // Every dependent symbol (p, pd, pdd, their Jacobians, pdd at qdd = 0) and
  // every intermediate is a definition of the programs: computed once, and
  // only where an entry point needs it.
  void define_dependents(const model::Kinematics& k) {
    for (const auto& d : k.dependents) definitions_.push_back({d.symbols.symbol, d.value});
    for (const auto& d : k.dependents) definitions_.push_back({d.symbols.rate, d.rate});
    for (const auto& d : k.dependents) definitions_.push_back({d.symbols.acceleration, d.acceleration});
    for (const auto& d : k.dependents) {
      for (std::size_t j = 0; j < d.jacobian.size(); ++j) {
        if (d.jacobian_symbols[j] != d.jacobian[j]) definitions_.push_back({d.jacobian_symbols[j], d.jacobian[j]});
      }
    }
    definitions_.insert(definitions_.end(), k.intermediates.begin(), k.intermediates.end());
  }

  std::vector<EntryPoint> build_entry_points(const model::Kinematics& k, const model::SimplifyFunction& simplify) {
    std::vector<EntryPoint> entries;
    using BK = model::BodyKinematics;
    const std::size_t nb = k.bodies.size();
    const std::size_t nq = model_.coordinates().size();
    std::vector<Expr> mass;
    std::vector<Expr> inertia;
    for (const auto& b : model_.bodies()) {
      mass.push_back(b.mass());
      inertia.insert(inertia.end(), b.inertia().begin(), b.inertia().end());
    }
    const OutputArray R{"R", fmt::format("({} x 3 x 3)", nb), flatten(k.bodies, &BK::R)};
    const OutputArray x{"x", fmt::format("({} x 3)", nb), flatten(k.bodies, &BK::x)};
    const OutputArray v{"v", fmt::format("({} x 3)", nb), flatten(k.bodies, &BK::v)};
    const OutputArray w{"w", fmt::format("({} x 3)", nb), flatten(k.bodies, &BK::w)};
    const OutputArray a{"a", fmt::format("({} x 3)", nb), flatten(k.bodies, &BK::a)};
    const OutputArray dw{"dw", fmt::format("({} x 3)", nb), flatten(k.bodies, &BK::dw)};
    entries.push_back({"inertia", "Mass of every body and its inertia tensor at G in body axes.", {"param"},
                        {{"mass", fmt::format("({})", nb), mass}, {"inertia", fmt::format("({} x 3 x 3)", nb), inertia}}, {}});
    entries.push_back({"positions", "Positions only (to draw a scene).", {"t", "q", "param"}, {R, x}, {}});
    entries.push_back({"velocities", "Positions and velocities.", {"t", "q", "qd", "param"}, {R, x, v, w}, {}});
    entries.push_back({"accelerations", "Positions, velocities and accelerations.", {"t", "q", "qd", "qdd", "param"},
                        {R, x, v, w, a, dw}, {}});
    auto relative = [&](OutputArray o, auto field) {
      o.values = flatten(k.bodies, field, true);
      return o;
    };
    entries.push_back({"relative_accelerations",
                        "Each body's motion relative to its reference (reference_body; the ground for -1), in the\n"
                        "// reference's axes, as CAGeM emitted it: compose as EasyDyn did (runtime/relative_motion.hpp).",
                        {"t", "q", "qd", "qdd", "param"},
                        {relative(R, &BK::R), relative(x, &BK::x), relative(v, &BK::v), relative(w, &BK::w),
                         relative(a, &BK::a), relative(dw, &BK::dw)}, {}});
    const std::string pv_shape = fmt::format("({} x {} x 3)", nb, nq);
    if (options_.symbolic_partials) {
      entries.push_back({"partial_velocities", "Partial velocities dv/dqd and dw/dqd (symbolic).", {"t", "q", "param"},
                          {{"dv", pv_shape, flatten_partials(k.bodies, &BK::dv_dqd)},
                           {"dw", pv_shape, flatten_partials(k.bodies, &BK::dw_dqd)}}, {}});
      entries.push_back({"relative_partial_velocities",
                          "Partial velocities of each body's motion relative to its reference, in the reference's axes.",
                          {"t", "q", "param"},
                          {{"dv", pv_shape, flatten_partials(k.bodies, &BK::dv_dqd, true)},
                           {"dw", pv_shape, flatten_partials(k.bodies, &BK::dw_dqd, true)}}, {}});
      add_fused_kinematics(entries);
    } else {
      entries.push_back({"partial_velocities",
                          "Partial velocities dv/dqd and dw/dqd, numeric as in EasyDyn: velocities are affine in qd, so\n"
                          "// dv/dqd_j = v(qd = e_j) - v(qd = 0) exactly.",
                          {"t", "q", "param"}, {{"dv", pv_shape, {}}, {"dw", pv_shape, {}}}, numeric_partials_body(nb, nq)});
    }
    std::vector<Expr> p, pd, pdd;
    for (const auto& d : k.dependents) {
      p.push_back(d.symbols.symbol);
      pd.push_back(d.symbols.rate);
      pdd.push_back(d.symbols.acceleration);
    }
    const std::string dep_shape = fmt::format("({})", k.dependents.size());
    entries.push_back({"dependent_parameters", "Dependent parameters and their first and second time derivatives.",
                        {"t", "q", "qd", "qdd", "param"}, {{"p", dep_shape, p}, {"pd", dep_shape, pd}, {"pdd", dep_shape, pdd}}, {}});
    if (options_.equations_of_motion && wants_dynamics()) {
      model::Dynamics dyn = model::derive_dynamics(model_, k, simplify);
      if (simplify) model::reduce_trigonometry(dyn, k);
      definitions_.insert(definitions_.end(), dyn.definitions.begin(), dyn.definitions.end());
      entries.push_back({"mass_matrix", "Mass matrix M(q, t).", {"t", "q", "param"},
                          {{"M", fmt::format("({} x {})", nq, nq), dyn.mass_matrix}}, {}});
      entries.push_back({"bias_forces", "h(q, qd, t): inertia terms at qdd = 0 and gravity (M qdd + h = Q).",
                          {"t", "q", "qd", "param"}, {{"h", fmt::format("({})", nq), dyn.bias}}, {}});
      add_dynamics(entries);
      entries.push_back({"inverse_dynamics", "tau = M qdd + h by recursive Newton-Euler (linear in the bodies).",
                          {"t", "q", "qd", "qdd", "param"}, {{"tau", fmt::format("({})", nq), dyn.inverse}}, {}});
      why_not_ = dyn.why_not;
      if (!dyn.forward.empty() && options_.dynamics != DynamicsMethod::mass_matrix) add_forward_dynamics(entries, dyn);
    }
    return entries;
  }

  // Accelerations and partial velocities in one call, absolute and relative:
  // the sines, cosines and rotations both need are computed once. The
  // partial velocities are named dv_dqd and dw_dqd here (dw is the angular
  // acceleration).
  static void add_fused_kinematics(std::vector<EntryPoint>& entries) {
    const auto entry = [&](const std::string& name) {
      return *std::find_if(entries.begin(), entries.end(), [&](const EntryPoint& p) { return p.name == name; });
    };
    const auto fuse = [&](const std::string& kinematics, const std::string& partials, const std::string& doc) {
      EntryPoint fused = entry(kinematics);
      fused.name = kinematics + "_partials";
      fused.doc = doc;
      for (OutputArray o : entry(partials).outputs) {
        o.name += "_dqd";
        fused.outputs.push_back(std::move(o));
      }
      entries.push_back(std::move(fused));
    };
    fuse("accelerations", "partial_velocities",
         "accelerations and partial_velocities in one call (dv_dqd, dw_dqd: their dv, dw).");
    fuse("relative_accelerations", "relative_partial_velocities",
         "relative_accelerations and relative_partial_velocities in one call (dv_dqd, dw_dqd: their dv, dw).");
  }

  // The runtime's hot path: M and h in one call, so that the sines, cosines
  // and rotations they share are computed once, with (for force elements)
  // the kinematics and partial velocities of the same state.
  void add_dynamics(std::vector<EntryPoint>& entries) const {
    const auto find = [&](const std::string& entry, const std::string& array) {
      const auto e = std::find_if(entries.begin(), entries.end(), [&](const EntryPoint& p) { return p.name == entry; });
      return *std::find_if(e->outputs.begin(), e->outputs.end(), [&](const OutputArray& o) { return o.name == array; });
    };
    const std::vector<std::string> inputs{"t", "q", "qd", "param"};
    const OutputArray M = find("mass_matrix", "M"), h = find("bias_forces", "h");
    entries.push_back({"dynamics", "M and h together (the runtime's hot path without force elements).", inputs, {M, h}, {}});
    if (!options_.symbolic_partials) return;  // numeric partial velocities are a loop, not a program to fuse
    const OutputArray R = find("positions", "R"), x = find("positions", "x"), v = find("velocities", "v"),
                      w = find("velocities", "w"), dv = find("partial_velocities", "dv"),
                      dw = find("partial_velocities", "dw");
    entries.push_back({"dynamics_positions",
                       "M and h with the positions and partial velocities that force elements read.", inputs,
                       {M, h, R, x, dv, dw}, {}});
    entries.push_back({"dynamics_velocities",
                       "M and h with the positions, velocities and partial velocities that force elements read.",
                       inputs, {M, h, R, x, v, w, dv, dw}, {}});
  }

  void add_forward_dynamics(std::vector<EntryPoint>& entries, const model::Dynamics& dyn) const {
    const std::size_t nq = model_.coordinates().size();
    const std::vector<std::string> inputs{"t", "q", "qd", "tau", "param"};
    entries.push_back({"forward_dynamics_pivots",
                       "qdd = M^-1 (tau - h) by the articulated-body algorithm, with each coordinate's pivot d of\n"
                       "// the LDL^T factorization of its body's D = S^T I^A S and the diagonal entry of D it came from.",
                       inputs,
                       {{"qdd_solved", fmt::format("({})", nq), dyn.forward},
                        {"pivots", fmt::format("({} x 2)", nq), dyn.pivots}},
                       {}});
    entries.push_back({"forward_dynamics",
                      "qdd = M^-1 (tau - h) without M; returns -1, or the first coordinate whose pivot is not\n"
                      "// positive or is below 64 ulps of its diagonal entry (then qdd is not to be used).",
                      inputs, {{"qdd", fmt::format("({})", nq), {}}}, forward_dynamics_body(nq)});
  }

  std::string numeric_partials_body(std::size_t nb, std::size_t nq) const {
    return fmt::format(
        "  double R[{0} * 9], x[{0} * 3], v0[{0} * 3], w0[{0} * 3], v[{0} * 3], w[{0} * 3];\n"
        "  double qd[{1}] = {{}};\n"
        "  velocities(t, q, qd, param, R, x, v0, w0);\n"
        "  for (int j = 0; j < {1}; ++j) {{\n"
        "    qd[j] = 1.0;\n"
        "    velocities(t, q, qd, param, R, x, v, w);\n"
        "    qd[j] = 0.0;\n"
        "    for (int i = 0; i < {0}; ++i) {{\n"
        "      for (int k = 0; k < 3; ++k) {{\n"
        "        dv[(i * {1} + j) * 3 + k] = v[i * 3 + k] - v0[i * 3 + k];\n"
        "        dw[(i * {1} + j) * 3 + k] = w[i * 3 + k] - w0[i * 3 + k];\n"
        "      }}\n"
        "    }}\n"
        "  }}\n",
        nb, nq);
  }

  bool selected(std::string_view name) const {
    const auto& wanted = options_.entry_points;
    return wanted.empty() || std::find(wanted.begin(), wanted.end(), name) != wanted.end();
  }

  bool wants_dynamics() const {
    return std::any_of(std::begin(kDynamicsEntryPoints), std::end(kDynamicsEntryPoints),
                       [&](const char* name) { return selected(name); });
  }

  bool wants_absolute_motion() const {
    const auto relative = [](const std::string& name) {
      return std::find(std::begin(kRelativeEntryPoints), std::end(kRelativeEntryPoints), name) !=
             std::end(kRelativeEntryPoints);
    };
    const auto& wanted = options_.entry_points;
    return wanted.empty() || !std::all_of(wanted.begin(), wanted.end(), relative);
  }

  // Options::entry_points, with what their hand-written bodies call.
  void select_entry_points(std::vector<EntryPoint>& entries) const {
    if (options_.entry_points.empty()) return;
    std::vector<std::string> names;
    for (const EntryPoint& e : entries) names.push_back(e.name);
    const bool dynamics_derived = std::find(names.begin(), names.end(), "dynamics") != names.end();
    if (options_.equations_of_motion && !dynamics_derived) {
      names.insert(names.end(), std::begin(kDynamicsEntryPoints), std::end(kDynamicsEntryPoints));
    }
    for (const std::string& name : options_.entry_points) {
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        const std::string why = choice_ ? fmt::format("; accelerations: {}", choice_->reason) : "";
        throw ModelError(fmt::format("entry point '{}' is not emitted with these options (emitted: {}{})", name,
                                     fmt::join(names, ", "), why));
      }
    }
    const auto called = [&](const EntryPoint& e) {
      return std::any_of(entries.begin(), entries.end(), [&](const EntryPoint& caller) {
        return selected(caller.name) && !caller.body.empty() &&
               std::any_of(std::begin(kBodyCalls), std::end(kBodyCalls), [&](const auto& call) {
                 return caller.name == call.first && e.name == call.second;
               });
      });
    };
    std::erase_if(entries, [&](const EntryPoint& e) { return !selected(e.name) && !called(e); });
  }

  bool emitted(std::string_view name) const {
    return std::any_of(entries_.begin(), entries_.end(), [&](const EntryPoint& e) { return e.name == name; });
  }

  // Keeps forward_dynamics (and its program) or drops it, once for the model:
  // the plain derivation, compared entry point by entry point, follows the
  // first one's choice.
  void choose_dynamics(std::vector<EntryPoint>& entries) {
    const auto named = [&](const char* name) {
      return std::find_if(entries.begin(), entries.end(), [&](const EntryPoint& e) { return e.name == name; });
    };
    const auto recursive = named("forward_dynamics_pivots");
    if (!choice_ && named("dynamics") != entries.end()) choice_ = weigh(entries, recursive, named("dynamics"));
    if (recursive != entries.end() && !(choice_ && choice_->recursive)) {
      entries.erase(named("forward_dynamics_pivots"));
      entries.erase(named("forward_dynamics"));
    }
  }

  DynamicsChoice weigh(const std::vector<EntryPoint>& entries, std::vector<EntryPoint>::const_iterator recursive,
                       std::vector<EntryPoint>::const_iterator mass_matrix) const {
    DynamicsChoice c;
    const std::size_t nq = model_.coordinates().size();
    c.mass_matrix_operations = compile(*mass_matrix)->operation_count().total() + nq * nq * nq / 6 + nq * nq;
    if (recursive == entries.end()) {
      c.reason = why_not_.empty() ? "mass matrix (as asked)"
                                  : fmt::format("mass matrix: the recursive forward dynamics does not apply ({})", why_not_);
      return c;
    }
    c.recursive_operations = compile(*recursive)->operation_count().total();
    const bool fewer = c.recursive_operations < c.mass_matrix_operations;
    c.recursive = options_.dynamics == DynamicsMethod::recursive ||
                  (options_.dynamics == DynamicsMethod::automatic && fewer);
    const char* how = options_.dynamics == DynamicsMethod::automatic ? "fewer operations" : "as asked";
    c.reason = fmt::format("{} ({}): recursive forward dynamics {} operations, mass matrix {} (dynamics() and "
                           "nq³/6 + nq² for Cholesky and solve)",
                           c.recursive ? "recursive" : "mass matrix", how, c.recursive_operations,
                           c.mass_matrix_operations);
    return c;
  }

  // forward_dynamics: the emitted pivots checked as the runtime's SpdSolver
  // checks M's, so that a failing call can fall back to M and its diagnostics.
  std::string forward_dynamics_body(std::size_t nq) const {
    return fmt::format(
        "  double pivots[{0}];\n"
        "  forward_dynamics_pivots(t, q, qd, tau, param, qdd, pivots);\n"
        "  for (int j = 0; j < {1}; ++j) {{\n"
        "    const double d = pivots[2 * j], diagonal = pivots[2 * j + 1];\n"
        "    if (!(d > 0.0 && d > {2} * diagonal)) return j;\n"
        "  }}\n"
        "  return -1;\n",
        2 * nq, nq, symbolic::cpp_literal(kSingularPivotRatio));
  }

  std::string signature(const EntryPoint& e, bool definition) const {
    std::vector<std::string> params;
    const std::string unused = definition ? "[[maybe_unused]] " : "";
    for (const std::string& in : e.inputs) {
      params.push_back(in == "t" ? unused + "double t" : fmt::format("{}const double* {}", unused, in));
    }
    for (const OutputArray& o : e.outputs) params.push_back(fmt::format("{}double* {}", unused, o.name));
    return fmt::format("{} {}{}({})", return_type(e), definition ? struct_name_ + "::" : "", e.name, fmt::join(params, ", "));
  }

  // The entry point's own program, or nothing for a hand-written body.
  std::optional<symbolic::Program> compile(const EntryPoint& e) const {
    if (!e.body.empty()) return std::nullopt;
    std::vector<Expr> inputs;
    for (const std::string& in : e.inputs) {
      const auto& syms = symbols_.at(in);
      inputs.insert(inputs.end(), syms.begin(), syms.end());
    }
    std::vector<Expr> outputs;
    for (const OutputArray& o : e.outputs) outputs.insert(outputs.end(), o.values.begin(), o.values.end());
    return symbolic::compile_program(inputs, outputs, definitions_);
  }

  // How a whole entry point's program names its inputs and outputs.
  symbolic::CppNaming naming(const EntryPoint& e) const {
    symbolic::CppNaming naming;
    for (const std::string& in : e.inputs) {
      const std::size_t n = symbols_.at(in).size();
      for (std::size_t i = 0; i < n; ++i) naming.inputs.push_back(input_element(in, i));
    }
    for (const OutputArray& o : e.outputs) {
      naming.outputs.reserve(naming.outputs.size() + o.values.size());
      for (std::size_t i = 0; i < o.values.size(); ++i) naming.outputs.push_back(element(o.name, i));
      naming.output_arrays.emplace_back(o.name, o.values.size());
    }
    return naming;
  }

  // "\n<signature> {\n<body>}\n"
  std::string function_text(const EntryPoint& e, const std::string& body) const {
    std::string out = "\n";
    out += signature(e, true);
    out += " {\n";
    out += body;
    out += "}\n";
    return out;
  }

  // A deterministic 64-bit fingerprint of the emitted text: FNV-1a's step
  // over little-endian 8-byte words in 4 independent lanes,
  // then over the lanes' bytes: byte by byte, its chain of dependent
  // multiplications would be slow to run over the whole source.
  static std::uint64_t text_hash(std::string_view text) {
    constexpr std::uint64_t kBasis = 14695981039346656037ull, kPrime = 1099511628211ull;
    constexpr std::size_t kLanes = 4, kBlock = 8 * kLanes;
    const auto byte = [&](std::size_t i) { return std::uint64_t{static_cast<unsigned char>(text[i])}; };
    std::array<std::uint64_t, kLanes> lanes;
    lanes.fill(kBasis);
    std::size_t i = 0;
    for (; i + kBlock <= text.size(); i += kBlock) {
      for (std::size_t k = 0; k < kLanes; ++k) {
        std::uint64_t word = 0;
        for (std::size_t b = 0; b < 8; ++b) word |= byte(i + 8 * k + b) << (8 * b);
        lanes[k] = (lanes[k] ^ word) * kPrime;
      }
    }
    std::uint64_t h = kBasis;
    for (std::uint64_t lane : lanes) {
      for (std::size_t b = 0; b < 8; ++b) h = (h ^ ((lane >> (8 * b)) & 0xff)) * kPrime;
    }
    for (; i < text.size(); ++i) h = (h ^ byte(i)) * kPrime;
    return h;
  }

  // Every file including the header refers to this model's own symbol, so the
  // linker pulls this model's object even from a static library, and a second,
  // different model of the same struct name then collides with it on
  // symdyn_model_<struct> (docs/emitted_interface.md, link-time guard).
  std::string link_guard_reference(const std::string& unique) const {
    return fmt::format(
        "// Link-time guard: two different models named {name} in one program fail to link\n"
        "// (multiple definition of {ns}::symdyn_model_{name}).\n"
        "extern const char {unique}[];\n"
        "[[gnu::used]] static const char* const symdyn_model_{name}_link = {unique};\n\n",
        fmt::arg("name", struct_name_), fmt::arg("ns", options_.name_space), fmt::arg("unique", unique));
  }

  std::string link_guard_definitions(const std::string& unique) const {
    const std::string what = fmt::format("\"model '{}', variant '{}'\"", model_.name(), variant_);
    return fmt::format("\n// Link-time guard: see the header.\nextern const char symdyn_model_{0}[];\n"
                       "const char symdyn_model_{0}[] = {1};\nconst char {2}[] = {1};\n",
                       struct_name_, what, unique);
  }

  // The header up to its link guard, which closes its namespace.
  std::string emit_header(const std::vector<EmittedFunction>& stats) const {
    const auto& coords = model_.coordinates();
    std::vector<std::string> q_names, body_names, param_names;
    std::vector<double> q0, qd0, param_defaults, gravity;
    std::vector<std::string> references;
    for (const auto& c : coords) {
      q_names.push_back(c.q.name());
      q0.push_back(c.initial);
      qd0.push_back(c.initial_rate);
    }
    const std::vector<int> refs = model_.reference_indices();
    for (std::size_t i = 0; i < model_.bodies().size(); ++i) {
      body_names.push_back(model_.bodies()[i].name());
      references.push_back(fmt::format("{}", refs[i]));
    }
    for (const auto& p : model_.parameters()) {
      param_names.push_back(p.symbol.name());
      param_defaults.push_back(p.value);
    }
    for (Expr g : model_.gravity()) gravity.push_back(g.number().to_double());
    std::string counts;
    for (const auto& s : stats) {
      counts += fmt::format("//   {:<22} {}\n", s.name,
                            !s.program ? hand_written_note(s.name) : fmt::format("{} operations: {}", s.operations.total(), s.operations.str()));
    }
    // What the runtime may take from the struct (runtime/model.hpp).
    const bool eom = options_.equations_of_motion && emitted("mass_matrix") && emitted("bias_forces");
    const std::string dynamics_line =
        eom ? fmt::format("// Accelerations: {}.\n", choice_ ? choice_->reason : "mass matrix") : "";
    const std::string only = options_.entry_points.empty()
                                 ? ""
                                 : fmt::format(", only {}", fmt::join(options_.entry_points, ", "));
    std::string declarations;
    for (const EntryPoint& e : entries_) {
      declarations += fmt::format("  // {}\n", e.doc);
      for (const OutputArray& o : e.outputs) declarations += fmt::format("  //   {} {}\n", o.name, o.shape);
      declarations += fmt::format("  static {};\n", signature(e, false));
    }
    const std::size_t nparam = model_.parameters().size();
    return fmt::format(
        "// Generated by symdyn from model '{model}', variant '{variant}'. Do not edit.\n"
        "// Options: simplify={simplify}, partial velocities {partials}, equations of motion {eom_option}{only}.\n"
        "// Operation counts per entry point:\n{counts}"
        "{dynamics_line}"
        "// Interface: docs/emitted_interface.md. Arrays are row-major.\n"
        "#pragma once\n\n"
        "namespace {ns} {{\n\n"
        "struct {name} {{\n"
        "  static constexpr const char* model = \"{model}\";\n"
        "  static constexpr const char* variant = \"{variant}\";\n"
        "  static constexpr int nq = {nq};\n"
        "  static constexpr int nbody = {nbody};\n"
        "  static constexpr int ndep = {ndep};\n"
        "  static constexpr int nparam = {nparam};\n"
        "  static constexpr bool has_equations_of_motion = {eom};\n"
        "  static constexpr bool has_inverse_dynamics = {inverse};  // inverse_dynamics emitted\n"
        "  static constexpr bool has_forward_dynamics = {recursive};  // forward_dynamics emitted\n\n"
        "  static constexpr const char* q_names[{nq}] = {q_names};\n"
        "  static constexpr const char* body_names[{nbody}] = {body_names};\n"
        "  static constexpr const char* param_names[{nparam1}] = {param_names};\n"
        "  static constexpr double param_defaults[{nparam1}] = {param_defaults};\n"
        "  static constexpr double q_initial[{nq}] = {q0};\n"
        "  static constexpr double qd_initial[{nq}] = {qd0};\n"
        "  static constexpr double gravity[3] = {gravity};\n"
        "  static constexpr int reference_body[{nbody}] = {{{refs}}};\n\n"
        "{declarations}"
        "{diagnostics}"
        "}};\n\n",
        fmt::arg("model", model_.name()), fmt::arg("variant", variant_), fmt::arg("simplify", options_.simplify),
        fmt::arg("partials", options_.symbolic_partials ? "symbolic" : "numeric"),
        fmt::arg("eom_option", options_.equations_of_motion), fmt::arg("only", only), fmt::arg("eom", eom),
        fmt::arg("counts", counts), fmt::arg("dynamics_line", dynamics_line),
        fmt::arg("inverse", emitted("inverse_dynamics")), fmt::arg("recursive", emitted("forward_dynamics")), fmt::arg("ns", options_.name_space),
        fmt::arg("name", struct_name_), fmt::arg("nq", coords.size()), fmt::arg("nbody", model_.bodies().size()),
        fmt::arg("ndep", model_.dependents().size()), fmt::arg("nparam", nparam),
        fmt::arg("nparam1", at_least_one(nparam)), fmt::arg("q_names", string_array_literal(q_names)),
        fmt::arg("body_names", string_array_literal(body_names)),
        fmt::arg("param_names", string_array_literal(param_names)),
        fmt::arg("param_defaults", array_literal(param_defaults)), fmt::arg("q0", array_literal(q0)),
        fmt::arg("qd0", array_literal(qd0)), fmt::arg("gravity", array_literal(gravity)),
        fmt::arg("refs", fmt::join(references, ", ")), fmt::arg("declarations", declarations),
        fmt::arg("diagnostics", diagnostics_declarations()));
  }

  // Cold diagnostics (docs/emitted_interface.md): the runtime calls
  // domain_arguments only after it met a non-finite value, to name the dependent
  // parameter and the function; the angle sequences only once M is singular.
  std::string diagnostics_declarations() const {
    std::vector<std::string> dependent_names, functions, owners, bodies, coordinates, axes;
    for (const auto& d : model_.dependents()) dependent_names.push_back(d.symbol.name());
    for (const model::DomainCheck& c : checks_) {
      functions.push_back(c.function);
      owners.push_back(c.dependent);
    }
    for (const model::AngleSequence& a : sequences_) {
      bodies.push_back(std::to_string(a.body));
      for (int q : a.coordinates) coordinates.push_back(std::to_string(q));
      axes.push_back(std::string(a.axes.begin(), a.axes.end()));
    }
    const auto ints = [](std::vector<std::string> v) {
      if (v.empty()) v.push_back("0");
      return fmt::format("{{{}}}", fmt::join(v, ", "));
    };
    const std::size_t ndep = model_.dependents().size(), ndomain = checks_.size(), nseq = sequences_.size();
    return fmt::format(
        "\n  // Cold diagnostics, for error messages only (docs/emitted_interface.md).\n"
        "  static constexpr const char* dependent_names[{ndep1}] = {dependent_names};  // (ndep)\n"
        "  // Operations of the dependent parameters with a restricted domain, innermost first.\n"
        "  static constexpr int ndomain = {ndomain};\n"
        "  static constexpr const char* domain_dependents[{ndomain1}] = {owners};  // (ndomain) whose operation\n"
        "  static constexpr const char* domain_functions[{ndomain1}] = {functions};  // (ndomain)\n"
        "  // Their arguments at (t, q): arguments (ndomain x 2), the base and exponent of pow, else (x, 0).\n"
        "  static void domain_arguments(double t, const double* q, const double* param, double* arguments);\n"
        "  // Bodies rotated by three elementary rotations by coordinates, singular where the first and\n"
        "  // third axes align.\n"
        "  static constexpr int nangle_sequences = {nseq};\n"
        "  static constexpr int angle_sequence_body[{nseq1}] = {bodies};  // (nangle_sequences)\n"
        "  static constexpr int angle_sequence_q[{nseq3}] = {coordinates};  // (nangle_sequences x 3)\n"
        "  static constexpr const char* angle_sequence_axes[{nseq1}] = {axes};  // (nangle_sequences) \"zyx\"\n",
        fmt::arg("ndep1", at_least_one(ndep)), fmt::arg("dependent_names", string_array_literal(dependent_names)),
        fmt::arg("ndomain", ndomain), fmt::arg("ndomain1", at_least_one(ndomain)), fmt::arg("owners", string_array_literal(owners)),
        fmt::arg("functions", string_array_literal(functions)), fmt::arg("nseq", nseq),
        fmt::arg("nseq1", at_least_one(nseq)), fmt::arg("bodies", ints(bodies)),
        fmt::arg("nseq3", at_least_one(3 * nseq)), fmt::arg("coordinates", ints(coordinates)),
        fmt::arg("axes", string_array_literal(axes)));
  }

  // The arguments of every domain check, from the dependent parameters as written.
  std::string domain_arguments_text() const {
    std::vector<Expr> inputs, outputs;
    symbolic::CppNaming naming;
    for (const char* in : {"t", "q", "param"}) {
      const auto& syms = symbols_.at(in);
      inputs.insert(inputs.end(), syms.begin(), syms.end());
      for (std::size_t i = 0; i < syms.size(); ++i) naming.inputs.push_back(input_element(in, i));
    }
    for (const model::DomainCheck& c : checks_) {
      outputs.push_back(c.argument);
      outputs.push_back(c.exponent);
    }
    for (std::size_t i = 0; i < outputs.size(); ++i) naming.outputs.push_back(element("arguments", i));
    std::vector<symbolic::Definition> definitions;
    for (const auto& d : model_.dependents()) definitions.push_back({d.symbol, d.expression});
    const symbolic::Program program = symbolic::compile_program(inputs, outputs, definitions);
    return fmt::format("\n// Cold: only to name a domain error.\n[[gnu::cold]] void {}::domain_arguments([[maybe_unused]] "
                       "double t, [[maybe_unused]] const double* q, [[maybe_unused]] const double* param, "
                       "[[maybe_unused]] double* arguments) {{\n{}}}\n",
                       struct_name_, symbolic::emit_cpp(program, naming));
  }

  const model::Model model_;
  std::string variant_;
  std::string basename_;
  const Options& options_;
  std::string struct_name_;
  std::unordered_map<std::string, std::vector<Expr>> symbols_;
  std::vector<symbolic::Definition> definitions_;  // of the current derivation
  std::vector<EntryPoint> entries_;
  std::vector<model::DomainCheck> checks_;
  std::vector<model::AngleSequence> sequences_;
  std::optional<model::Kinematics> plain_kinematics_;  // made first when simplifying (run())
  std::optional<DynamicsChoice> choice_;  // made by the first derivation
  std::string why_not_;                   // the recursive forward dynamics does not apply
};

}  // namespace

void check_options(std::string_view variant, std::string_view basename, const Options& options) {
  model::check_name(variant, "variant");  // first: the default basename is made of it
  model::check_identifier(basename, "basename");
  if (options.name_space.empty()) throw ModelError("namespace is empty (the code would be in an anonymous namespace)");
  std::string_view rest = options.name_space;
  for (std::size_t sep = rest.find("::");; sep = rest.find("::")) {
    if (auto problem = model::identifier_problem(rest.substr(0, sep))) {
      throw ModelError(fmt::format("namespace '{}': '{}' {}", options.name_space, rest.substr(0, sep), *problem));
    }
    if (sep == std::string_view::npos) break;
    rest.remove_prefix(sep + 2);
  }
}

GeneratedCode generate(const model::Model& model, std::string_view variant, std::string_view basename,
                       const Options& options) {
  check_options(variant, basename, options);
  model.validate();  // first, so that errors speak of the model as written
  try {
    return Emitter(model.with_shared_motions_relative(), model::angle_sequences(model), variant, basename, options).run();
  } catch (const symbolic::SymbolicError& e) {
    throw ModelError(fmt::format("model '{}' variant '{}': {}", model.name(), variant, e.what()));
  }
}

}  // namespace symdyn::codegen
