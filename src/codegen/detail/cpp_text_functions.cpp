// The entry points' definitions: each a whole program (a short model), or
// calls of internal functions (parts) shared between the entry points that
// need the same statements (a long one, symbolic::emit_cpp_shared).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <stdexcept>

#include <symdyn/codegen/detail/cpp_text.hpp>

namespace symdyn::codegen::detail {
namespace {

// "\n<signature> {\n<body>}\n"
std::string function_text(const TextContext& c, const EntryPoint& e, const std::string& body) {
  std::string out = "\n";
  out += signature(*e.spec, c.basename, true);
  out += " {\n";
  out += body;
  out += "}\n";
  return out;
}

// The entry point in GeneratedCode::functions, without its program yet.
EmittedFunction& emitted(const EntryPoint& e, std::vector<EmittedFunction>& functions) {
  EmittedFunction& f = functions.emplace_back();
  f.name = e.name();
  for (Input in : e.spec->inputs) f.inputs.emplace_back(input_name(in));
  for (const OutputArray& o : e.outputs) f.outputs.emplace_back(o.name, o.values.size());
  return f;
}

// How a whole entry point's program names its inputs and outputs.
symbolic::CppNaming naming(const TextContext& c, const EntryPoint& e) {
  symbolic::CppNaming naming;
  for (Input in : e.spec->inputs) {
    const std::size_t n = c.inputs.size(in);
    for (std::size_t i = 0; i < n; ++i) naming.inputs.push_back(input_element(in, i));
  }
  for (const OutputArray& o : e.outputs) {
    naming.outputs.reserve(naming.outputs.size() + o.values.size());
    for (std::size_t i = 0; i < o.values.size(); ++i) naming.outputs.push_back(element(o.name, i));
    naming.output_arrays.emplace_back(o.name, o.values.size());
    naming.sparse_arrays.push_back(o.sparse);
  }
  return naming;
}

// Each entry point its own function, each a definition of its own.
void emit_whole(const TextContext& c, Derivation& d, GeneratedCode& code, FunctionTexts& texts) {
  for (std::size_t i = 0; i < d.entries.size(); ++i) {
    const EntryPoint& entry = d.entries[i];
    EmittedFunction& f = emitted(entry, code.functions);
    if (!entry.hand_written()) f.program = std::move(d.whole[i]);
    texts.definitions.push_back(function_text(
        c, entry, f.program ? symbolic::emit_cpp(*f.program, naming(c, entry)) : entry.body));
    if (f.program) f.operations = f.program->operation_count();
  }
}

// A part's parameters: the arrays it reads and writes. __restrict on every
// array (outputs never overlap inputs, nor each other) tells the compiler
// that a store changes no input, output or scratch entry it has read, so
// nothing is read again and its alias queries end at once.
std::string part_parameters(const symbolic::CppPart& part, const symbolic::CppNaming& naming) {
  std::vector<std::string> params;
  for (std::size_t a : part.input_arrays) {
    const std::string& in = naming.input_arrays[a].first;
    params.push_back(in == "t" ? "double t" : fmt::format("const double* __restrict {}", in));
  }
  for (std::size_t a : part.output_arrays)
    params.push_back(fmt::format("double* __restrict {}", naming.output_arrays[a].first));
  if (part.scratch) params.push_back(fmt::format("double* __restrict {}", naming.scratch));
  return fmt::format("{}", fmt::join(params, ", "));
}

// The parts as internal functions, each a definition. noinline keeps the
// compiler from gluing them back into one function.
void part_functions(const Derivation& d, const symbolic::CppShared& shared,
                    const symbolic::CppNaming& naming, FunctionTexts& texts) {
  std::vector<std::string_view> names;  // of the entry points with a program, by function
  for (const EntryPoint& e : d.entries) {
    if (!e.hand_written()) names.push_back(e.name());
  }
  for (std::size_t p = 0; p < shared.parts.size(); ++p) {
    const symbolic::CppPart& part = shared.parts[p];
    std::vector<std::string_view> users;
    for (std::size_t f : part.functions) users.push_back(names[f]);
    const std::string params = part_parameters(part, naming);
    std::string text =
        fmt::format("\n// Part {} of {}, run by {}.\n[[gnu::noinline]] void part{}({}) {{\n", p + 1,
                    shared.parts.size(), fmt::join(users, ", "), p, params);
    text += part.body;
    text += "}\n";
    texts.definitions.push_back(std::move(text));
    texts.declarations += fmt::format("void part{}({});\n", p, params);
  }
}

// An entry point's body: its scratch array, then a call of each of its parts.
std::string part_calls(const Derivation& d, std::size_t entry,
                       const std::vector<symbolic::CppPart>& parts,
                       const symbolic::CppFunctionParts& mine, const symbolic::CppNaming& naming) {
  const EntryPoint& e = d.entries[entry];
  std::string out;
  if (mine.scratch_size > 0)
    out += fmt::format("  double {}[{}];\n", naming.scratch, mine.scratch_size);
  for (std::size_t p : mine.parts) {
    const symbolic::CppPart& part = parts[p];
    std::vector<std::string> args;
    for (std::size_t a : part.input_arrays) {
      const std::string& in = naming.input_arrays[a].first;
      const auto takes = [&](Input i) { return input_name(i) == in; };
      if (std::none_of(e.spec->inputs.begin(), e.spec->inputs.end(), takes)) {
        throw std::logic_error(
            fmt::format("generate: {} needs input {}, which it does not take", e.name(), in));
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

// Every entry point with a program runs the parts its outputs need, the
// parts (internal functions), then the entry points in order, which call them.
void emit_shared(const TextContext& c, const Derivation& d, GeneratedCode& code,
                 FunctionTexts& texts) {
  symbolic::CppNaming naming;
  for (Input in : kInputs) {
    const std::size_t n = c.inputs.size(in);
    naming.input_arrays.emplace_back(input_name(in), n);
    for (std::size_t i = 0; i < n; ++i) naming.inputs.push_back(input_element(in, i));
  }
  for (const OutputArray& a : d.arrays) {
    for (std::size_t i = 0; i < a.values.size(); ++i) naming.outputs.push_back(element(a.name, i));
    naming.output_arrays.emplace_back(a.name, a.values.size());
    naming.sparse_arrays.push_back(a.sparse);
  }
  // The outputs of each entry point with a program.
  const std::vector<std::vector<std::size_t>> functions = entry_outputs(d);
  const symbolic::CppShared shared =
      symbolic::emit_cpp_shared(d.program, naming, functions, c.options.part_instructions);
  part_functions(d, shared, naming, texts);
  for (std::size_t e = 0, fn = 0; e < d.entries.size(); ++e) {
    const EntryPoint& entry = d.entries[e];
    EmittedFunction& f = emitted(entry, code.functions);
    if (entry.hand_written()) {
      texts.calls += function_text(c, entry, entry.body);
      continue;
    }
    f.program = d.program.subprogram(functions[fn], c.inputs.indices(entry.spec->inputs));
    f.operations = f.program->operation_count();
    texts.calls +=
        function_text(c, entry, part_calls(d, e, shared.parts, shared.functions[fn], naming));
    ++fn;
  }
}

}  // namespace

std::string signature(const EntryPointSpec& spec, std::string_view struct_name, bool definition) {
  std::vector<std::string> params;
  const std::string unused = definition ? "[[maybe_unused]] " : "";
  for (Input in : spec.inputs) {
    params.push_back(in == Input::t ? unused + "double t"
                                    : fmt::format("{}const double* {}", unused, input_name(in)));
  }
  for (const OutputSpec& o : spec.outputs)
    params.push_back(fmt::format("{}double* {}", unused, o.name));
  return fmt::format("{} {}{}{}({})", spec.returns, definition ? struct_name : "",
                     definition ? "::" : "", spec.name, fmt::join(params, ", "));
}

FunctionTexts emit_functions(const TextContext& c, Derivation& d, GeneratedCode& code) {
  FunctionTexts texts;
  texts.shared = d.whole.empty();
  if (texts.shared) {
    emit_shared(c, d, code, texts);
  } else {
    emit_whole(c, d, code, texts);
  }
  return texts;
}

}  // namespace symdyn::codegen::detail
