// The header: what was emitted and how long it is, the struct's constants
// (sizes, names, initial state), one declaration per entry point with its
// catalogue doc and output shapes, and the cold diagnostics.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include <symdyn/codegen/detail/cpp_text.hpp>

namespace symdyn::codegen::detail {
namespace {

// The operation count of each entry point, or what its hand-written body does.
std::string operation_counts(const std::vector<EntryPoint>& entries,
                             const std::vector<EmittedFunction>& functions) {
  std::string out;
  for (std::size_t i = 0; i < functions.size(); ++i) {
    const EmittedFunction& f = functions[i];
    out += fmt::format(
        "//   {:<22} {}\n", f.name,
        f.program ? fmt::format("{} operations: {}", f.operations.total(), f.operations.str())
                  : std::string(entries[i].spec->note));
  }
  return out;
}

// What the header says of an output written sparsely (OutputSpec::sparse).
constexpr std::string_view kSparseNote =
    ", sparse: only its nonzeros are written, zero it once before the first call";

// Each entry point's doc, its outputs' shapes, its declaration. A doc's
// further lines start at the line's beginning, as they always have.
std::string declarations(const TextContext& c, const std::vector<EntryPoint>& entries) {
  std::string out;
  for (const EntryPoint& e : entries) {
    std::string doc(e.spec->doc);
    for (std::size_t n = doc.find('\n'); n != std::string::npos; n = doc.find('\n', n + 4))
      doc.replace(n, 1, "\n// ");
    out += fmt::format("  // {}\n", doc);
    for (const OutputArray& o : e.outputs)
      out += fmt::format("  //   {} {}{}\n", o.name, o.shape, o.sparse ? kSparseNote : "");
    out += fmt::format("  static {};\n", signature(*e.spec, c.basename, false));
  }
  return out;
}

// The closed loops' facts the runtime reads (runtime/model.hpp), for a model that has them.
std::string loops_declarations(const model::Model& model) {
  if (model.loops().empty()) return "";
  std::vector<std::string> names, of_equation, bodies, axes;
  for (std::size_t l = 0; l < model.loops().size(); ++l) {
    const model::Loop& loop = model.loops()[l];
    names.push_back(loop.name);
    bodies.push_back(fmt::format("{}, {}", loop.body_a, loop.body_b));
    for (std::size_t k = 0; k < loop.equations.size(); ++k) {
      of_equation.push_back(fmt::format("{}", l));
      axes.push_back(fmt::format("{}", loop.body_a >= 0 ? loop.axes[k] : -1));
    }
  }
  return fmt::format(
      "  // Closed loops: q holds the {0} independent coordinates, then the {1} implicit "
      "dependent\n"
      "  // parameters, which the loops' {1} equations determine (constraints, "
      "constraint_bias).\n"
      "  static constexpr int nindependent = {0};\n"
      "  static constexpr int nloop = {2};\n"
      "  static constexpr const char* loop_names[{2}] = {3};\n"
      "  static constexpr int constraint_loop[{1}] = {{{4}}};  // the loop of each equation\n"
      "  // close_loop's bodies a, b of each loop (-1, -1: a loop given by its equations), and\n"
      "  // the axis (0, 1, 2: x, y, z) of the gap each equation is a component of (or -1).\n"
      "  static constexpr int loop_bodies[{5}] = {{{6}}};\n"
      "  static constexpr int constraint_axis[{1}] = {{{7}}};\n\n",
      model.num_independent(), model.num_implicit(), names.size(), string_array_literal(names),
      fmt::join(of_equation, ", "), 2 * names.size(), fmt::join(bodies, ", "),
      fmt::join(axes, ", "));
}

}  // namespace

std::string header_text(const TextContext& c, const std::vector<EntryPoint>& entries,
                        const std::vector<EmittedFunction>& functions,
                        const std::optional<DynamicsChoice>& choice,
                        const std::string& derivatives) {
  const model::Model& model = c.model;
  const Options& options = c.options;
  const auto& coords = model.coordinates();
  std::vector<std::string> q_names, body_names, param_names;
  std::vector<double> q0, qd0, param_defaults, gravity;
  std::vector<std::string> references;
  for (const auto& q : coords) {
    q_names.push_back(q.q.name());
    q0.push_back(q.initial);
    qd0.push_back(q.initial_rate);
  }
  const std::vector<int> refs = model.reference_indices();
  for (std::size_t i = 0; i < model.bodies().size(); ++i) {
    body_names.push_back(model.bodies()[i].name());
    references.push_back(fmt::format("{}", refs[i]));
  }
  for (const auto& p : model.parameters()) {
    param_names.push_back(p.symbol.name());
    param_defaults.push_back(p.value);
  }
  for (model::Expr g : model.gravity()) gravity.push_back(g.number().to_double());
  // The flags the runtime reads (runtime/model.hpp): which of these entry points it may call.
  const auto emitted = [&](std::string_view name) {
    return std::any_of(entries.begin(), entries.end(),
                       [&](const EntryPoint& e) { return e.name() == name; });
  };
  const bool eom = options.equations_of_motion && emitted("mass_matrix") && emitted("bias_forces");
  const std::string dynamics_line =
      eom ? fmt::format("// Accelerations: {}.\n", choice ? choice->reason : "mass matrix") : "";
  const bool derivatives_emitted = emitted("inverse_dynamics_derivatives");
  const std::string derivatives_line =
      derivatives_emitted ? fmt::format("// Derivatives: {}.\n", derivatives) : "";
  const std::string only = options.entry_points.empty()
                               ? ""
                               : fmt::format(", only {}", fmt::join(options.entry_points, ", "));
  const std::size_t nparam = model.parameters().size();
  return fmt::format(
      "// Generated by symdyn from model '{model}', variant '{variant}'. Do not edit.\n"
      "// Options: simplify={simplify}, partial velocities {partials}, equations of motion "
      "{eom_option}{only}.\n"
      "// Operation counts per entry point:\n{counts}"
      "{dynamics_line}"
      "{derivatives_line}"
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
      "  static constexpr bool has_forward_dynamics = {recursive};  // forward_dynamics emitted\n"
      "  static constexpr bool has_inverse_dynamics_derivatives = {derivatives};  // "
      "inverse_dynamics_derivatives "
      "emitted\n\n"
      "  static constexpr const char* q_names[{nq}] = {q_names};\n"
      "  static constexpr const char* body_names[{nbody}] = {body_names};\n"
      "  static constexpr const char* param_names[{nparam1}] = {param_names};\n"
      "  static constexpr double param_defaults[{nparam1}] = {param_defaults};\n"
      "  static constexpr double q_initial[{nq}] = {q0};\n"
      "  static constexpr double qd_initial[{nq}] = {qd0};\n"
      "  static constexpr double gravity[3] = {gravity};\n"
      "  static constexpr int reference_body[{nbody}] = {{{refs}}};\n\n"
      "{loops}"
      "{declarations}"
      "{diagnostics}"
      "}};\n\n",
      fmt::arg("model", model.name()), fmt::arg("variant", c.variant),
      fmt::arg("simplify", options.simplify),
      fmt::arg("partials", options.symbolic_partials ? "symbolic" : "numeric"),
      fmt::arg("eom_option", options.equations_of_motion), fmt::arg("only", only),
      fmt::arg("eom", eom), fmt::arg("counts", operation_counts(entries, functions)),
      fmt::arg("dynamics_line", dynamics_line), fmt::arg("derivatives_line", derivatives_line),
      fmt::arg("derivatives", derivatives_emitted),
      fmt::arg("inverse", emitted("inverse_dynamics")),
      fmt::arg("recursive", emitted("forward_dynamics")), fmt::arg("ns", options.name_space),
      fmt::arg("name", c.basename), fmt::arg("nq", coords.size()),
      fmt::arg("nbody", model.bodies().size()), fmt::arg("ndep", model.dependents().size()),
      fmt::arg("nparam", nparam), fmt::arg("nparam1", at_least_one(nparam)),
      fmt::arg("q_names", string_array_literal(q_names)),
      fmt::arg("body_names", string_array_literal(body_names)),
      fmt::arg("param_names", string_array_literal(param_names)),
      fmt::arg("param_defaults", number_array_literal(param_defaults)),
      fmt::arg("q0", number_array_literal(q0)), fmt::arg("qd0", number_array_literal(qd0)),
      fmt::arg("gravity", number_array_literal(gravity)),
      fmt::arg("refs", fmt::join(references, ", ")), fmt::arg("loops", loops_declarations(model)),
      fmt::arg("declarations", declarations(c, entries)),
      fmt::arg("diagnostics", diagnostics_declarations(c)));
}

}  // namespace symdyn::codegen::detail
