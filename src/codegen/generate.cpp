// codegen::generate, in three steps of one job each: select the entry points
// of the catalogue (detail/selection, detail/entry_points), derive them
// (detail/derivation, detail/dynamics_choice), print their C++
// (detail/cpp_text*).
#include <fmt/format.h>

#include <symdyn/codegen/detail/cpp_text.hpp>
#include <symdyn/codegen/detail/derivation.hpp>
#include <symdyn/codegen/detail/input_symbols.hpp>
#include <symdyn/codegen/detail/selection.hpp>
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/diagnostics.hpp>
#include <symdyn/model/errors.hpp>
#include <symdyn/model/identifier.hpp>
#include <symdyn/symbolic/errors.hpp>

namespace symdyn::codegen {

using model::ModelError;

void check_options(std::string_view variant, std::string_view basename, const Options& options) {
  model::check_name(variant, "variant");  // first: the default basename is made of it
  model::check_identifier(basename, "basename");
  if (options.sources == 0 || options.sources > kMaxSources) {
    throw ModelError(
        fmt::format("sources is {} (it must be 1 to {})", options.sources, kMaxSources));
  }
  if (options.source_bytes == 0) throw ModelError("source_bytes is 0 (it must be at least 1)");
  if (options.name_space.empty())
    throw ModelError("namespace is empty (the code would be in an anonymous namespace)");
  std::string_view rest = options.name_space;
  for (std::size_t sep = rest.find("::");; sep = rest.find("::")) {
    if (auto problem = model::identifier_problem(rest.substr(0, sep))) {
      throw ModelError(fmt::format("namespace '{}': '{}' {}", options.name_space,
                                   rest.substr(0, sep), *problem));
    }
    if (sep == std::string_view::npos) break;
    rest.remove_prefix(sep + 2);
  }
}

GeneratedCode generate(const model::Model& model, std::string_view variant,
                       std::string_view basename, const Options& options) {
  check_options(variant, basename, options);
  model.validate();  // first, so that errors speak of the model as written
  try {
    // The angle sequences of the model as written: sharing motions makes some relative.
    const std::vector<model::AngleSequence> sequences = model::angle_sequences(model);
    const model::Model shared = model.with_shared_motions_relative();
    const std::vector<model::DomainCheck> checks = model::domain_checks(shared);
    const detail::InputSymbols inputs(shared);
    const detail::Selection selection(options.entry_points, options.equations_of_motion);
    detail::Deriver deriver(shared, options, selection, inputs);
    detail::Derivation chosen = deriver.run();
    const detail::TextContext text{shared, variant, basename, options, inputs, checks, sequences};
    return detail::emit_code(text, std::move(chosen), deriver.dynamics_choice(),
                             deriver.derivatives_reason());
  } catch (const symbolic::SymbolicError& e) {
    throw ModelError(fmt::format("model '{}' variant '{}': {}", model.name(), variant, e.what()));
  }
}

}  // namespace symdyn::codegen
