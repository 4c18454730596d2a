#pragma once
// The C++ text of a derivation (docs/emitted_interface.md): the header with
// the struct's constants and declarations, the entry points' definitions
// (each whole, or calling parts shared between them), the cold diagnostics,
// and the link guard. Printing only: what to print, the derivation decided.
// The private header of cpp_text*.cpp, one file per piece of text.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/codegen/detail/derivation.hpp>
#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/detail/input_symbols.hpp>
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/diagnostics.hpp>

namespace symdyn::codegen::detail {

// What every piece of text is printed for.
struct TextContext {
  const model::Model& model;
  std::string_view variant;
  std::string_view basename;  // of the files, and the struct's name
  const Options& options;
  const InputSymbols& inputs;
  const std::vector<model::DomainCheck>& checks;
  const std::vector<model::AngleSequence>& sequences;
};

// The header and source, and each entry point's program (cpp_text.cpp).
// `derivatives`: why the derivatives are of the form they are (Deriver::derivatives_reason).
GeneratedCode emit_code(const TextContext& c, Derivation&& d,
                        const std::optional<DynamicsChoice>& choice,
                        const std::string& derivatives);

// cpp_text_functions.cpp: the declaration ("void positions(double t, ...)",
// without `static`) or the definition's head ("void <struct>::positions(
// [[maybe_unused]] double t, ...)") of an entry point.
std::string signature(const EntryPointSpec& spec, std::string_view struct_name, bool definition);
// The entry points' definitions, and each entry point to code.functions
// with its program (moved out of d.whole).
struct FunctionTexts {
  bool shared = false;  // definitions are the parts, calls the entry points that call them
  std::vector<std::string> definitions;  // in order, each whole: any source file may hold it
  std::string declarations;              // of the parts ("void part0(...);" lines)
  std::string calls;                     // for the first source file, after the definitions
};
FunctionTexts emit_functions(const TextContext& c, Derivation& d, GeneratedCode& code);

// cpp_text_header.cpp: the header up to its link guard, which closes its namespace.
std::string header_text(const TextContext& c, const std::vector<EntryPoint>& entries,
                        const std::vector<EmittedFunction>& functions,
                        const std::optional<DynamicsChoice>& choice,
                        const std::string& derivatives);

// cpp_text_diagnostics.cpp: the struct's cold diagnostics, and the source's domain_arguments().
std::string diagnostics_declarations(const TextContext& c);
std::string domain_arguments_text(const TextContext& c);

// cpp_text_link_guard.cpp: a 64-bit fingerprint of the emitted text, and the
// guard's reference (header) and definitions (source) under the name `unique`.
std::uint64_t text_hash(std::string_view text);
std::string link_guard_reference(const TextContext& c, const std::string& unique);
std::string link_guard_definitions(const TextContext& c, const std::string& unique);

// Literals of the header's arrays (cpp_text.cpp): {"a", "b"} or {nullptr},
// {1.5, 0.0} or {0.0}, and the size an array of n > 0 entries is declared with.
std::string string_array_literal(const std::vector<std::string>& values);
std::string number_array_literal(const std::vector<double>& values);
std::size_t at_least_one(std::size_t n);

}  // namespace symdyn::codegen::detail
