// Cold diagnostics (docs/emitted_interface.md): the runtime calls
// domain_arguments only after it met a non-finite value, to name the
// dependent parameter and the function; it reads the angle sequences only
// once M is singular.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <symdyn/codegen/detail/cpp_text.hpp>

namespace symdyn::codegen::detail {
namespace {

std::string int_array_literal(std::vector<std::string> values) {
  if (values.empty()) values.push_back("0");
  return fmt::format("{{{}}}", fmt::join(values, ", "));
}

}  // namespace

std::string diagnostics_declarations(const TextContext& c) {
  std::vector<std::string> dependent_names, functions, owners, bodies, coordinates, axes;
  for (const auto& d : c.model.dependents()) dependent_names.push_back(d.symbol.name());
  for (const model::DomainCheck& check : c.checks) {
    functions.push_back(check.function);
    owners.push_back(check.dependent);
  }
  for (const model::AngleSequence& a : c.sequences) {
    bodies.push_back(std::to_string(a.body));
    for (int q : a.coordinates) coordinates.push_back(std::to_string(q));
    axes.push_back(std::string(a.axes.begin(), a.axes.end()));
  }
  const std::size_t ndep = c.model.dependents().size(), ndomain = c.checks.size(),
                    nseq = c.sequences.size();
  return fmt::format(
      "\n  // Cold diagnostics, for error messages only (docs/emitted_interface.md).\n"
      "  static constexpr const char* dependent_names[{ndep1}] = {dependent_names};  // (ndep)\n"
      "  // Operations of the dependent parameters with a restricted domain, innermost first.\n"
      "  static constexpr int ndomain = {ndomain};\n"
      "  static constexpr const char* domain_dependents[{ndomain1}] = {owners};  // (ndomain) "
      "whose operation\n"
      "  static constexpr const char* domain_functions[{ndomain1}] = {functions};  // (ndomain)\n"
      "  // Their arguments at (t, q): arguments (ndomain x 3), the argument (the base of pow), "
      "the\n  // exponent of pow (else 0), and the magnitude of the terms the argument is a sum "
      "of.\n"
      "  static void domain_arguments(double t, const double* q, const double* param, double* "
      "arguments);\n"
      "  // Bodies rotated by three elementary rotations by coordinates, singular where the first "
      "and\n"
      "  // third axes align.\n"
      "  static constexpr int nangle_sequences = {nseq};\n"
      "  static constexpr int angle_sequence_body[{nseq1}] = {bodies};  // (nangle_sequences)\n"
      "  static constexpr int angle_sequence_q[{nseq3}] = {coordinates};  // (nangle_sequences x "
      "3)\n"
      "  static constexpr const char* angle_sequence_axes[{nseq1}] = {axes};  // "
      "(nangle_sequences) \"zyx\"\n",
      fmt::arg("ndep1", at_least_one(ndep)),
      fmt::arg("dependent_names", string_array_literal(dependent_names)),
      fmt::arg("ndomain", ndomain), fmt::arg("ndomain1", at_least_one(ndomain)),
      fmt::arg("owners", string_array_literal(owners)),
      fmt::arg("functions", string_array_literal(functions)), fmt::arg("nseq", nseq),
      fmt::arg("nseq1", at_least_one(nseq)), fmt::arg("bodies", int_array_literal(bodies)),
      fmt::arg("nseq3", at_least_one(3 * nseq)),
      fmt::arg("coordinates", int_array_literal(coordinates)),
      fmt::arg("axes", string_array_literal(axes)));
}

// The arguments of every domain check, from the dependent parameters as written.
std::string domain_arguments_text(const TextContext& c) {
  std::vector<model::Expr> inputs, outputs;
  symbolic::CppNaming naming;
  for (Input in : {Input::t, Input::q, Input::param}) {
    const auto& symbols = c.inputs[in];
    inputs.insert(inputs.end(), symbols.begin(), symbols.end());
    for (std::size_t i = 0; i < symbols.size(); ++i) naming.inputs.push_back(input_element(in, i));
  }
  for (const model::DomainCheck& check : c.checks) {
    outputs.push_back(check.argument);
    outputs.push_back(check.exponent);
    outputs.push_back(check.scale);
  }
  for (std::size_t i = 0; i < outputs.size(); ++i)
    naming.outputs.push_back(element("arguments", i));
  std::vector<symbolic::Definition> definitions;
  for (const auto& d : c.model.dependents()) definitions.push_back({d.symbol, d.expression});
  const symbolic::Program program = symbolic::compile_program(inputs, outputs, definitions);
  return fmt::format(
      "\n// Cold: only to name a domain error.\n[[gnu::cold]] void {}::domain_arguments("
      "[[maybe_unused]] double t, [[maybe_unused]] const double* q, "
      "[[maybe_unused]] const double* param, [[maybe_unused]] double* arguments) {{\n{}}}\n",
      c.basename, symbolic::emit_cpp(program, naming));
}

}  // namespace symdyn::codegen::detail
