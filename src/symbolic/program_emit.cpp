// Printing a program as C++ statements.
#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <string>

#include "symbolic/print.hpp"
#include "symbolic/program.hpp"

namespace symdyn::symbolic {

std::string emit_cpp(const Program& program, const CppNaming& naming) {
  if (naming.inputs.size() != program.input_count() || naming.outputs.size() != program.output_count()) {
    throw UsageError(fmt::format("emit_cpp: naming has {} inputs and {} outputs; the program has {} and {}",
                                 naming.inputs.size(), naming.outputs.size(), program.input_count(),
                                 program.output_count()));
  }
  // What each slot reads as, in an operand position and as a whole statement's right side.
  std::vector<std::string> operand(program.slot_count());
  std::vector<std::string> whole(program.slot_count());
  std::string out;
  int next_temporary = 0;
  auto define = [&](std::uint32_t slot, std::string_view format, const std::vector<std::string>& args,
                    const std::string& constant) {
    const std::string name = naming.temporary_prefix + std::to_string(next_temporary++);
    // indent "const" type name " = " value ";": appended, as fmt would print it.
    out.append(naming.indent).append("const ").append(naming.scalar_type).append(" ").append(name).append(" = ");
    fmt::format_to(std::back_inserter(out), fmt::runtime(format), args[0], args[1], constant, "");
    out.append(";\n");
    operand[slot] = whole[slot] = name;
  };
  for (const Instruction& ins : program.instructions()) {
    const std::uint32_t r = ins.results[0];
    const OpcodeInfo& op = info(ins.op);
    // Only loads and pow print their constant ({2}); formatting a double is not free.
    const bool prints_constant = op.format.find("{2}") != std::string_view::npos;
    const std::string literal = prints_constant ? cpp_literal(ins.constant) : std::string();
    if (ins.op == Opcode::Const || ins.op == Opcode::Input) {  // loads print inline
      const std::string& name = ins.op == Opcode::Input ? naming.inputs[ins.input] : literal;
      whole[r] = fmt::format(fmt::runtime(op.format), "", "", literal, name);
      const bool negative = ins.op == Opcode::Const && std::signbit(ins.constant);
      operand[r] = negative ? fmt::format("({})", whole[r]) : whole[r];
      continue;
    }
    std::vector<std::string> args(2);
    for (int a = 0; a < op.arity; ++a) args[a] = operand[ins.args[a]];
    define(r, op.format, args, literal);
    if (op.results == 2) define(ins.results[1], op.format2, args, literal);
  }
  for (std::size_t i = 0; i < program.output_count(); ++i) {
    out += fmt::format("{}{} = {};\n", naming.indent, naming.outputs[i], whole[program.output_slots()[i]]);
  }
  return out;
}

}  // namespace symdyn::symbolic
