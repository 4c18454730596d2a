// Printing a program as C++ statements.
#include <fmt/format.h>

#include <cmath>

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
    const std::string name = fmt::format("{}{}", naming.temporary_prefix, next_temporary++);
    const std::string value = fmt::format(fmt::runtime(format), args[0], args[1], constant, "");
    out += fmt::format("{}const {} {} = {};\n", naming.indent, naming.scalar_type, name, value);
    operand[slot] = whole[slot] = name;
  };
  for (const Instruction& ins : program.instructions()) {
    const std::uint32_t r = ins.results[0];
    const OpcodeInfo& op = info(ins.op);
    const std::string literal = cpp_literal(ins.constant);
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
