// Printing a program as C++ statements, in one piece or in parts.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <string_view>

#include <symdyn/symbolic/print.hpp>
#include <symdyn/symbolic/program.hpp>

namespace symdyn::symbolic {
namespace {

constexpr int kNoPart = -1;  // loads: printed inline, in no part
using Mask = std::uint64_t;  // a set of functions, bit f for function f
constexpr std::size_t kMaxFunctions = 64;

// A part: output arrays it zeroes first, computing instructions (indices,
// in program order), then the outputs it assigns at its end.
struct Part {
  std::vector<std::size_t> zeroed;  // output arrays
  std::vector<std::size_t> instructions;
  std::vector<std::size_t> late_outputs;
  Mask functions = 0;
};

// Where each computing instruction and each output goes, and which values cross parts.
struct PartPlan {
  std::vector<Part> parts;          // in the order they run
  std::vector<int> part_of_slot;    // (slot_count) defining part, kNoPart for loads
  std::vector<bool> at_definition;  // (output_count) assigned right after its value's definition
  std::vector<bool> unassigned;     // (output_count) a zero its zeroed array already holds
  std::vector<std::int64_t>
      scratch_of;  // (slot_count) scratch entry, -1 if the value stays in its part
  std::vector<std::size_t> scratch_top;  // (parts) 1 + the highest entry its values use, 0 if none
};

bool is_load(const Instruction& ins) {
  return ins.op == Opcode::Const || ins.op == Opcode::Input;
}

// Appends an opcode's C++ format (program.hpp: "{0}*{1}", "std::pow({0}, {2})")
// with {i} replaced by fields[i], as fmt would print it. Why not fmt: parsing
// the format again for every instruction was most of the printing time.
void append_format(std::string& out, std::string_view format,
                   const std::array<std::string_view, 4>& fields) {
  for (std::size_t i = 0; i < format.size(); ++i) {
    const char c = format[i];
    if ((c == '{' || c == '}') && i + 1 < format.size() && format[i + 1] == c) {  // "{{" or "}}"
      out += c;
      ++i;
    } else if (c == '{' && i + 2 < format.size() && format[i + 2] == '}' && format[i + 1] >= '0' &&
               format[i + 1] <= '3') {
      out.append(fields[static_cast<std::size_t>(format[i + 1] - '0')]);
      i += 2;
    } else {
      out += c;
    }
  }
}

// Whether each slot is a constant +0.0 (all bits clear).
std::vector<bool> positive_zeros(const Program& program) {
  std::vector<bool> zero(program.slot_count(), false);
  for (const Instruction& i : program.instructions()) {
    zero[i.results[0]] = i.op == Opcode::Const && i.constant == 0.0 && !std::signbit(i.constant);
  }
  return zero;
}

// The output arrays zeroed whole by one loop before their other elements are
// assigned (see kZeroedArrayShare), by array, and the outputs they hold
// already (+0.0), by output. Only an array wanted by one set of functions is.
std::pair<std::vector<bool>, std::vector<bool>> zeroed_arrays(const Program& program,
                                                              const CppNaming& naming,
                                                              const std::vector<Mask>& wanted_by) {
  const auto outputs = program.output_slots();
  const std::vector<bool> zero = positive_zeros(program);
  std::vector<bool> zeroed(naming.output_arrays.size(), false), unassigned(outputs.size(), false);
  std::size_t first = 0;  // of the current array
  for (std::size_t a = 0; a < naming.output_arrays.size(); ++a) {
    const std::size_t end = first + naming.output_arrays[a].second;
    std::size_t zeros = 0;
    bool one_set = true;
    for (std::size_t o = first; o < end; ++o) {
      zeros += zero[outputs[o]];
      one_set = one_set && wanted_by[o] == wanted_by[first];
    }
    zeroed[a] =
        one_set && end - first >= kMinZeroedArray && zeros * kZeroedArrayShare >= end - first;
    for (std::size_t o = first; zeroed[a] && o < end; ++o) unassigned[o] = zero[outputs[o]];
    first = end;
  }
  return {zeroed, unassigned};
}

// Which functions want each output: bit f when function f lists it.
std::vector<Mask> functions_of_outputs(const Program& program,
                                       std::span<const std::vector<std::size_t>> functions) {
  if (functions.size() > kMaxFunctions) {
    throw UsageError(
        fmt::format("emit_cpp_shared: {} functions, at most {}", functions.size(), kMaxFunctions));
  }
  std::vector<Mask> wanted_by(program.output_count(), 0);
  for (std::size_t f = 0; f < functions.size(); ++f) {
    for (std::size_t o : functions[f]) {
      if (o >= wanted_by.size())
        throw UsageError(
            fmt::format("emit_cpp_shared: function {} lists output {}; the program has {}", f, o,
                        wanted_by.size()));
      wanted_by[o] |= Mask{1} << f;
    }
  }
  for (std::size_t o = 0; o < wanted_by.size(); ++o) {
    if (wanted_by[o] == 0)
      throw UsageError(fmt::format("emit_cpp_shared: no function wants output {}", o));
  }
  return wanted_by;
}

// Which functions need each instruction: those whose outputs depend on one of its results.
std::vector<Mask> functions_of_instructions(const Program& program,
                                            const std::vector<Mask>& wanted_by) {
  const auto ins = program.instructions();
  std::vector<Mask> of_slot(program.slot_count(), 0);
  for (std::size_t o = 0; o < wanted_by.size(); ++o)
    of_slot[program.output_slots()[o]] |= wanted_by[o];
  std::vector<Mask> of_instruction(ins.size(), 0);
  for (std::size_t k = ins.size(); k-- > 0;) {
    const OpcodeInfo& op = info(ins[k].op);
    Mask m = of_slot[ins[k].results[0]];
    if (op.results == 2) m |= of_slot[ins[k].results[1]];
    of_instruction[k] = m;
    for (int a = 0; a < op.arity; ++a) of_slot[ins[k].args[a]] |= m;
  }
  return of_instruction;
}

// Groups the computing instructions by the functions that need them, cuts
// each group into parts of at most `max` statements (0: no limit), and gives
// every value read after its defining part a scratch entry, lowest free first
// (free again from the part after its value's last reader). Statements are
// counted because a compiler's work grows with stores as much as with
// arithmetic: a computing instruction weighs 1 plus the outputs it assigns;
// other outputs weigh 1 each and go after the group's instructions, in
// output order; the loop zeroing an array weighs 1 and goes first.
PartPlan plan_parts(const Program& program, const CppNaming& naming,
                    std::span<const std::vector<std::size_t>> functions, std::size_t max) {
  PartPlan plan;
  const auto ins = program.instructions();
  const auto outputs = program.output_slots();
  const std::vector<Mask> wanted_by = functions_of_outputs(program, functions);
  const std::vector<Mask> needed_by = functions_of_instructions(program, wanted_by);
  auto [zeroed, unassigned] = zeroed_arrays(program, naming, wanted_by);
  plan.unassigned = std::move(unassigned);
  std::vector<std::size_t> defined_by(program.slot_count(),
                                      ins.size());  // instruction index, ins.size() for loads
  for (std::size_t k = 0; k < ins.size(); ++k) {
    if (is_load(ins[k])) continue;
    for (int r = 0; r < info(ins[k].op).results; ++r) defined_by[ins[k].results[r]] = k;
  }
  // Outputs assigned at their value's definition, by slot (in output order), and the others.
  plan.at_definition.assign(outputs.size(), false);
  std::vector<std::size_t> assigned_with(ins.size(), 0);
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const std::size_t k = defined_by[outputs[o]];
    if (k < ins.size() && needed_by[k] == wanted_by[o]) {
      plan.at_definition[o] = true;
      ++assigned_with[k];
    }
  }
  // The groups: arrays zeroed first, instructions (each weighing 1 + the
  // outputs assigned with it), then the outputs assigned at the end.
  struct Group {
    Mask functions = 0;
    std::size_t first =
        0;  // where it first appears: instruction index, or ins.size() + output index
    std::vector<std::size_t> zeroed;
    std::vector<std::pair<std::size_t, std::size_t>> instructions;  // (index, weight)
    std::vector<std::size_t> outputs;
    std::size_t weight = 0;
  };
  std::vector<Group> groups;
  std::map<Mask, std::size_t> group_of;
  auto group = [&](Mask m, std::size_t first) -> Group& {
    auto [it, inserted] = group_of.try_emplace(m, groups.size());
    if (inserted) groups.push_back({m, first, {}, {}, {}, 0});
    return groups[it->second];
  };
  for (std::size_t a = 0, first = 0; a < zeroed.size(); first += naming.output_arrays[a++].second) {
    if (!zeroed[a]) continue;
    Group& g = group(wanted_by[first], ins.size() + first);
    g.zeroed.push_back(a);
    ++g.weight;
  }
  for (std::size_t k = 0; k < ins.size(); ++k) {
    if (is_load(ins[k])) continue;
    Group& g = group(needed_by[k], k);
    g.instructions.emplace_back(k, 1 + assigned_with[k]);
    g.weight += 1 + assigned_with[k];
  }
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    if (plan.at_definition[o] || plan.unassigned[o]) continue;
    Group& g = group(wanted_by[o], ins.size() + o);
    g.outputs.push_back(o);
    ++g.weight;
  }
  std::sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) {
    const int na = std::popcount(a.functions), nb = std::popcount(b.functions);
    return na != nb ? na > nb : a.first < b.first;
  });
  plan.part_of_slot.assign(program.slot_count(), kNoPart);
  for (const Group& g : groups) {
    const std::size_t count = max > 0 && g.weight > max ? (g.weight + max - 1) / max : 1;
    const std::size_t per_part = std::max<std::size_t>(1, (g.weight + count - 1) / count);
    const std::size_t first = plan.parts.size();
    for (std::size_t p = 0; p < count; ++p) plan.parts.push_back({{}, {}, {}, g.functions});
    plan.parts[first].zeroed = g.zeroed;
    std::size_t done = g.zeroed.size();  // weight placed so far
    for (const auto& [k, weight] : g.instructions) {
      const std::size_t p = first + done / per_part;
      plan.parts[p].instructions.push_back(k);
      for (int r = 0; r < info(ins[k].op).results; ++r)
        plan.part_of_slot[ins[k].results[r]] = static_cast<int>(p);
      done += weight;
    }
    for (std::size_t o : g.outputs)
      plan.parts[first + std::min(done++ / per_part, count - 1)].late_outputs.push_back(o);
  }
  // One part: every output at its end, in order, as emit_cpp prints them.
  if (plan.parts.size() == 1) {
    plan.at_definition.assign(outputs.size(), false);
    plan.parts[0].late_outputs.clear();
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      if (!plan.unassigned[o]) plan.parts[0].late_outputs.push_back(o);
    }
  }
  // The last part to read each value: its instructions' and its outputs' readers.
  std::vector<int> last_reader(program.slot_count(), kNoPart);
  for (std::size_t p = 0; p < plan.parts.size(); ++p) {
    for (std::size_t k : plan.parts[p].instructions) {
      for (int a = 0; a < info(ins[k].op).arity; ++a)
        last_reader[ins[k].args[a]] = static_cast<int>(p);
    }
    for (std::size_t o : plan.parts[p].late_outputs) last_reader[outputs[o]] = static_cast<int>(p);
  }
  // Values by defining part, and by the part from which their entry is free.
  std::vector<std::vector<std::uint32_t>> defined(plan.parts.size()),
      released(plan.parts.size() + 1);
  for (std::uint32_t s = 0; s < program.slot_count(); ++s) {
    const int part = plan.part_of_slot[s];
    if (part == kNoPart || last_reader[s] <= part) continue;
    defined[static_cast<std::size_t>(part)].push_back(s);
    released[static_cast<std::size_t>(last_reader[s]) + 1].push_back(s);
  }
  plan.scratch_of.assign(program.slot_count(), -1);
  plan.scratch_top.assign(plan.parts.size(), 0);
  std::set<std::int64_t> free;
  std::int64_t entries = 0;
  for (std::size_t p = 0; p < plan.parts.size(); ++p) {
    for (std::uint32_t s : released[p]) free.insert(plan.scratch_of[s]);
    for (std::uint32_t s : defined[p]) {
      if (free.empty()) free.insert(entries++);
      plan.scratch_of[s] = *free.begin();
      free.erase(free.begin());
      plan.scratch_top[p] =
          std::max(plan.scratch_top[p], static_cast<std::size_t>(plan.scratch_of[s]) + 1);
    }
  }
  return plan;
}

// Prints the plan's parts. An array written sparsely (CppNaming::sparse_arrays)
// is planned as any other, and printed without its zeros: neither its loop
// nor its +0.0 elements one by one, which its caller zeroed once. So the
// parts are cut and ordered as for code that writes them, and that code
// differs from this one in those lines alone.
class Printer {
 public:
  Printer(const Program& program, const CppNaming& naming, const PartPlan& plan)
      : program_(program),
        naming_(naming),
        plan_(plan),
        operand_(program.slot_count()),
        whole_(program.slot_count()),
        declaration_(naming.indent + "const " + naming.scalar_type + " "),
        array_of_input_(arrays_of(naming.input_arrays)),
        array_of_output_(arrays_of(naming.output_arrays)) {
    input_of_slot_.assign(program.slot_count(), kNotInput);
    for (const Instruction& ins : program.instructions()) {
      if (is_load(ins)) load(ins);
      if (ins.op == Opcode::Input) input_of_slot_[ins.results[0]] = ins.input;
    }
    const auto outputs = program.output_slots();
    const std::vector<bool> zero = positive_zeros(program);
    unwritten_.assign(outputs.size(), false);
    for (std::size_t o = 0; o < outputs.size() && !naming.sparse_arrays.empty(); ++o)
      unwritten_[o] = naming.sparse_arrays[array_of_output_[o]] && zero[outputs[o]];
    // The outputs of each computed slot assigned at its definition, in output order (CSR:
    // first_output_, by_slot_).
    first_output_.assign(program.slot_count() + 1, 0);
    for (std::size_t o = 0; o < outputs.size(); ++o)
      first_output_[outputs[o] + 1] += plan.at_definition[o];
    for (std::size_t s = 0; s < program.slot_count(); ++s) first_output_[s + 1] += first_output_[s];
    by_slot_.resize(first_output_.back());
    std::vector<std::size_t> next(first_output_.begin(), first_output_.end() - 1);
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      if (plan.at_definition[o]) by_slot_[next[outputs[o]]++] = o;
    }
  }

  std::vector<CppPart> run() {
    std::vector<CppPart> parts;
    for (std::size_t p = 0; p < plan_.parts.size(); ++p) {
      part_ = CppPart{};
      const Part& layout = plan_.parts[p];
      for (std::size_t f = 0; f < kMaxFunctions; ++f) {
        if ((layout.functions >> f & 1) != 0) part_.functions.push_back(f);
      }
      for (std::size_t a : layout.zeroed) {
        if (naming_.sparse_arrays.empty() || !naming_.sparse_arrays[a]) zero(a);
      }
      for (std::size_t k : layout.instructions) print(program_.instructions()[k]);
      for (std::size_t o : layout.late_outputs) assign(o);
      // Later parts read this part's values from the scratch array.
      for (std::size_t k : layout.instructions) {
        const Instruction& ins = program_.instructions()[k];
        for (int r = 0; r < info(ins.op).results; ++r) {
          const std::uint32_t s = ins.results[r];
          if (plan_.scratch_of[s] >= 0)
            operand_[s] = whole_[s] = fmt::format("{}[{}]", naming_.scratch, plan_.scratch_of[s]);
        }
      }
      sort_unique(part_.input_arrays);
      sort_unique(part_.output_arrays);
      parts.push_back(std::move(part_));
    }
    return parts;
  }

 private:
  // arrays_of({(name, size)...}): the array of each element, or none if no arrays are named.
  static std::vector<std::size_t> arrays_of(
      const std::vector<std::pair<std::string, std::size_t>>& arrays) {
    std::vector<std::size_t> of;
    for (std::size_t a = 0; a < arrays.size(); ++a) of.insert(of.end(), arrays[a].second, a);
    return of;
  }
  static void sort_unique(std::vector<std::size_t>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }

  // Loads print inline: their texts once, for every part.
  void load(const Instruction& ins) {
    const std::uint32_t r = ins.results[0];
    const OpcodeInfo& op = info(ins.op);
    const std::string literal = ins.op == Opcode::Const ? cpp_literal(ins.constant) : std::string();
    const std::string& name = ins.op == Opcode::Input ? naming_.inputs[ins.input] : literal;
    append_format(whole_[r], op.format, {"", "", literal, name});
    const bool negative = ins.op == Opcode::Const && std::signbit(ins.constant);
    operand_[r] = negative ? "(" + whole_[r] + ")" : whole_[r];
  }

  void print(const Instruction& ins) {
    const OpcodeInfo& op = info(ins.op);
    // Only pow prints its constant ({2}) among computing instructions; formatting a double is not
    // free.
    const std::string literal = ins.op == Opcode::Pow ? cpp_literal(ins.constant) : std::string();
    // Views of the operands' texts: defining the results changes no operand's.
    std::array<std::string_view, 2> args{};
    for (int a = 0; a < op.arity; ++a) {
      args[static_cast<std::size_t>(a)] = operand_[ins.args[a]];
      note_read(ins.args[a]);
    }
    define(ins.results[0], op.format, args, literal);
    if (op.results == 2) define(ins.results[1], op.format2, args, literal);
  }

  void define(std::uint32_t slot, std::string_view format,
              const std::array<std::string_view, 2>& args, const std::string& constant) {
    const std::string name = naming_.temporary_prefix + std::to_string(next_temporary_++);
    // indent "const" type name " = " value ";": appended, as fmt would print it.
    out().append(declaration_).append(name).append(" = ");
    append_format(out(), format, {args[0], args[1], constant, ""});
    out().append(";\n");
    if (plan_.scratch_of[slot] >= 0) {  // read by a later part
      out().append(naming_.indent).append(naming_.scratch).append("[");
      out()
          .append(std::to_string(plan_.scratch_of[slot]))
          .append("] = ")
          .append(name)
          .append(";\n");
      part_.scratch = true;
    }
    operand_[slot] = whole_[slot] = name;
    for (std::size_t k = first_output_[slot]; k < first_output_[slot + 1]; ++k) {
      out()
          .append(naming_.indent)
          .append(naming_.outputs[by_slot_[k]])
          .append(" = ")
          .append(name)
          .append(";\n");
      note_write(by_slot_[k]);
    }
  }

  void assign(std::size_t o) {
    if (unwritten_[o]) return;
    const std::uint32_t slot = program_.output_slots()[o];
    note_read(slot);
    note_write(o);
    out()
        .append(naming_.indent)
        .append(naming_.outputs[o])
        .append(" = ")
        .append(whole_[slot])
        .append(";\n");
  }

  void zero(std::size_t array) {
    const auto& [name, size] = naming_.output_arrays[array];
    fmt::format_to(std::back_inserter(out()), "{}for (int i = 0; i < {}; ++i) {}[i] = 0.0;\n",
                   naming_.indent, size, name);
    part_.output_arrays.push_back(array);
  }

  void note_read(std::uint32_t slot) {
    const int part = plan_.part_of_slot[slot];
    if (part != kNoPart) {
      part_.scratch = part_.scratch || plan_.scratch_of[slot] >= 0;
    } else if (input_of_slot_[slot] != kNotInput && !array_of_input_.empty()) {
      part_.input_arrays.push_back(array_of_input_[input_of_slot_[slot]]);
    }
  }
  void note_write(std::size_t o) {
    if (!array_of_output_.empty()) part_.output_arrays.push_back(array_of_output_[o]);
  }

  std::string& out() { return part_.body; }

  const Program& program_;
  const CppNaming& naming_;
  const PartPlan& plan_;
  // What each slot reads as, in an operand position and as a whole statement's right side.
  std::vector<std::string> operand_;
  std::vector<std::string> whole_;
  const std::string declaration_;  // what every temporary's line starts with: "  const double "
  CppPart part_;                   // the part being printed
  int next_temporary_ = 0;
  std::vector<std::size_t> array_of_input_;  // (input_count) its input array; empty if none named
  std::vector<std::size_t>
      array_of_output_;  // (output_count) its output array; empty if none named
  static constexpr std::uint32_t kNotInput = ~0U;
  std::vector<std::uint32_t>
      input_of_slot_;            // (slot_count) the input a load reads, kNotInput otherwise
  std::vector<bool> unwritten_;  // (output_count) a zero of an array written sparsely
  // The outputs of slot s assigned at its definition are by_slot_[first_output_[s] ...
  // first_output_[s + 1] - 1].
  std::vector<std::size_t> first_output_;
  std::vector<std::size_t> by_slot_;
};

void check_naming(const Program& program, const CppNaming& naming) {
  if (naming.inputs.size() != program.input_count() ||
      naming.outputs.size() != program.output_count()) {
    throw UsageError(
        fmt::format("emit_cpp: naming has {} inputs and {} outputs; the program has {} and {}",
                    naming.inputs.size(), naming.outputs.size(), program.input_count(),
                    program.output_count()));
  }
  auto covered = [](const auto& arrays) {
    std::size_t n = 0;
    for (const auto& a : arrays) n += a.second;
    return n;
  };
  if (!naming.output_arrays.empty() && covered(naming.output_arrays) != program.output_count()) {
    throw UsageError(
        fmt::format("emit_cpp: naming's output arrays have {} elements; the program has {} outputs",
                    covered(naming.output_arrays), program.output_count()));
  }
  if (!naming.sparse_arrays.empty() && naming.sparse_arrays.size() != naming.output_arrays.size()) {
    throw UsageError(
        fmt::format("emit_cpp: naming says of {} arrays whether they are sparse; it "
                    "has {} output arrays",
                    naming.sparse_arrays.size(), naming.output_arrays.size()));
  }
  if (!naming.input_arrays.empty() && covered(naming.input_arrays) != program.input_count()) {
    throw UsageError(
        fmt::format("emit_cpp: naming's input arrays have {} elements; the program has {} inputs",
                    covered(naming.input_arrays), program.input_count()));
  }
}

}  // namespace

CppShared emit_cpp_shared(const Program& program, const CppNaming& naming,
                          std::span<const std::vector<std::size_t>> functions,
                          std::size_t max_instructions) {
  check_naming(program, naming);
  const PartPlan plan = plan_parts(program, naming, functions, max_instructions);
  CppShared code;
  code.parts = Printer(program, naming, plan).run();
  code.functions.resize(functions.size());
  for (std::size_t p = 0; p < code.parts.size(); ++p) {
    for (std::size_t f : code.parts[p].functions) {
      code.functions[f].parts.push_back(p);
      code.functions[f].scratch_size =
          std::max(code.functions[f].scratch_size, plan.scratch_top[p]);
    }
  }
  return code;
}

std::string emit_cpp(const Program& program, const CppNaming& naming) {
  std::vector<std::vector<std::size_t>> one(1, std::vector<std::size_t>(program.output_count()));
  std::iota(one[0].begin(), one[0].end(), std::size_t{0});
  CppShared code = emit_cpp_shared(program, naming, one, 0);
  return code.parts.empty() ? std::string()
                            : std::move(code.parts.front().body);  // no output: no part
}

}  // namespace symdyn::symbolic
