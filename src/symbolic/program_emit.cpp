// Printing a program as C++ statements, in one piece or in parts.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <set>
#include <string>
#include <string_view>

#include "symbolic/print.hpp"
#include "symbolic/program.hpp"

namespace symdyn::symbolic {
namespace {

constexpr int kNoPart = -1;  // loads: printed inline, in no part

// Where each computing instruction and each output goes, and which values cross parts.
struct PartPlan {
  std::size_t parts = 1;
  std::vector<int> part_of_slot;          // (slot_count) defining part, kNoPart for loads
  std::vector<std::size_t> output_part;   // (output_count) the part that assigns it
  std::vector<std::size_t> run_end;       // (output_count) > o where a loop assigns outputs o ... run_end - 1
  std::vector<std::int64_t> scratch_of;   // (slot_count) scratch entry, -1 if the value stays in its part
  std::size_t scratch_size = 0;
  // Several parts: a computed output is assigned right after its value is
  // defined (see emit_cpp_parts), not at the end of its part.
  bool outputs_at_definition = false;
};

bool is_load(const Instruction& ins) { return ins.op == Opcode::Const || ins.op == Opcode::Input; }

// Appends an opcode's C++ format (program.hpp: "{0}*{1}", "std::pow({0}, {2})")
// with {i} replaced by fields[i], as fmt would print it. Why not fmt: parsing
// the format again for every instruction was most of the printing time.
void append_format(std::string& out, std::string_view format, const std::array<std::string_view, 4>& fields) {
  for (std::size_t i = 0; i < format.size(); ++i) {
    const char c = format[i];
    if ((c == '{' || c == '}') && i + 1 < format.size() && format[i + 1] == c) {  // "{{" or "}}"
      out += c;
      ++i;
    } else if (c == '{' && i + 2 < format.size() && format[i + 2] == '}' && format[i + 1] >= '0' && format[i + 1] <= '3') {
      out.append(fields[static_cast<std::size_t>(format[i + 1] - '0')]);
      i += 2;
    } else {
      out += c;
    }
  }
}

// Runs of consecutive outputs of one array that are one constant, printed as
// loops: run_end[o] for the first output of each loop, 0 elsewhere. A run of
// at least kMinConstantRun is one loop; a shorter run of at least
// kMinZeroRun zeros is cut into loops of kZeroChunk (the last one shorter, or
// separate assignments if shorter than kMinZeroRun).
std::vector<std::size_t> constant_runs(const Program& program, const CppNaming& naming) {
  const auto outputs = program.output_slots();
  std::vector<std::size_t> run_end(outputs.size(), 0);
  std::vector<bool> constant(program.slot_count(), false);
  std::vector<bool> zero(program.slot_count(), false);  // +0.0: all bits clear
  for (const Instruction& i : program.instructions()) {
    constant[i.results[0]] = i.op == Opcode::Const;
    zero[i.results[0]] = i.op == Opcode::Const && i.constant == 0.0 && !std::signbit(i.constant);
  }
  std::size_t first = 0;  // of the current array
  for (const auto& [name, size] : naming.output_arrays) {
    for (std::size_t o = first; o < first + size;) {
      std::size_t e = o + 1;
      while (constant[outputs[o]] && e < first + size && outputs[e] == outputs[o]) ++e;
      if (constant[outputs[o]] && e - o >= kMinConstantRun) {
        run_end[o] = e;
      } else if (zero[outputs[o]] && e - o >= kMinZeroRun) {
        for (std::size_t c = o; c + kMinZeroRun <= e; c += kZeroChunk) run_end[c] = std::min(e, c + kZeroChunk);
      }
      o = e;
    }
    first += size;
  }
  return run_end;
}

// Cuts the program, if longer than `max` and `split_above` statements, into
// the fewest parts of at most `max` statements (0: no limit), as even as
// possible. Statements are counted because a compiler's work grows with stores as much as with arithmetic: a computing instruction
// weighs 1 plus the outputs it assigns; outputs that are loads (constants,
// inputs) weigh 1 each, a loop over a long constant run 1 in all, and are
// spread over the parts after every instruction, in output order.
// Every value read after its defining part gets a scratch entry, lowest free
// first: an entry is free again from the part after its value's last reader.
PartPlan plan_parts(const Program& program, const CppNaming& naming, std::size_t max, std::size_t split_above) {
  PartPlan plan;
  const auto ins = program.instructions();
  const auto outputs = program.output_slots();
  plan.run_end = constant_runs(program, naming);
  std::vector<std::size_t> readers_as_output(program.slot_count(), 0);
  for (std::uint32_t s : outputs) ++readers_as_output[s];
  std::vector<bool> loaded(program.slot_count(), false);
  std::size_t total = 0;
  for (const Instruction& i : ins) {
    if (is_load(i)) {
      loaded[i.results[0]] = true;
      continue;
    }
    total += 1 + readers_as_output[i.results[0]] + (info(i.op).results == 2 ? readers_as_output[i.results[1]] : 0);
  }
  // A long constant run's loop weighs 1 (`rep stos`); a short zero run's
  // loops weigh what they store, as the separate assignments did (g++ expands
  // them into stores), so that the parts are cut where they were.
  auto weight = [&](std::size_t o) -> std::size_t {
    if (!loaded[outputs[o]]) return 0;
    const std::size_t run = plan.run_end[o] > o ? plan.run_end[o] - o : 1;
    return run >= kMinConstantRun ? 1 : run;
  };
  for (std::size_t o = 0; o < outputs.size(); o = std::max(o + 1, plan.run_end[o])) total += weight(o);
  plan.part_of_slot.assign(program.slot_count(), kNoPart);
  if (max > 0 && total > std::max(max, split_above)) plan.parts = (total + max - 1) / max;
  const std::size_t per_part = std::max<std::size_t>(1, (total + plan.parts - 1) / plan.parts);
  std::vector<int> last_reader(program.slot_count(), kNoPart);
  std::size_t done = 0;  // weight placed so far
  for (const Instruction& i : ins) {
    if (is_load(i)) continue;
    const int part = static_cast<int>(done / per_part);
    const OpcodeInfo& op = info(i.op);
    for (int r = 0; r < op.results; ++r) {
      plan.part_of_slot[i.results[r]] = part;
      done += readers_as_output[i.results[r]];
    }
    for (int a = 0; a < op.arity; ++a) last_reader[i.args[a]] = std::max(last_reader[i.args[a]], part);
    ++done;
  }
  plan.output_part.resize(outputs.size());
  for (std::size_t o = 0; o < outputs.size();) {
    const int part = plan.part_of_slot[outputs[o]];
    const std::size_t end = std::max(o + 1, plan.run_end[o]);
    const std::size_t load_part = loaded[outputs[o]] ? std::min(done / per_part, plan.parts - 1) : 0;
    done += weight(o);
    for (; o < end; ++o) plan.output_part[o] = part != kNoPart ? static_cast<std::size_t>(part) : load_part;
  }
  // Values by defining part, and by the part from which their entry is free.
  std::vector<std::vector<std::uint32_t>> defined(plan.parts), released(plan.parts + 1);
  for (std::uint32_t s = 0; s < program.slot_count(); ++s) {
    const int part = plan.part_of_slot[s];
    if (part == kNoPart || last_reader[s] <= part) continue;
    defined[static_cast<std::size_t>(part)].push_back(s);
    released[static_cast<std::size_t>(last_reader[s]) + 1].push_back(s);
  }
  plan.outputs_at_definition = plan.parts > 1;
  plan.scratch_of.assign(program.slot_count(), -1);
  std::set<std::int64_t> free;
  for (std::size_t p = 0; p < plan.parts; ++p) {
    for (std::uint32_t s : released[p]) free.insert(plan.scratch_of[s]);
    for (std::uint32_t s : defined[p]) {
      if (free.empty()) free.insert(static_cast<std::int64_t>(plan.scratch_size++));
      plan.scratch_of[s] = *free.begin();
      free.erase(free.begin());
    }
  }
  return plan;
}

class Printer {
 public:
  Printer(const Program& program, const CppNaming& naming, const PartPlan& plan)
      : program_(program), naming_(naming), plan_(plan), operand_(program.slot_count()),
        whole_(program.slot_count()), declaration_(naming.indent + "const " + naming.scalar_type + " "),
        outputs_of_part_(plan.parts), slots_of_part_(plan.parts) {
    // Each part's outputs and slots, in order: looking them up among all of
    // them for every part would cost parts x outputs (chain_64: 200 parts).
    for (std::size_t i = 0; i < program.output_count(); ++i) outputs_of_part_[plan.output_part[i]].push_back(i);
    for (std::uint32_t s = 0; s < program.slot_count(); ++s) {
      if (plan.part_of_slot[s] != kNoPart) slots_of_part_[static_cast<std::size_t>(plan.part_of_slot[s])].push_back(s);
    }
    std::size_t first = 0;
    for (const auto& [name, size] : naming.output_arrays) {
      for (std::size_t i = first; i < first + size; ++i) array_of_output_.push_back({&name, first});
      first += size;
    }
    if (!plan.outputs_at_definition) return;
    // The outputs of each computed slot, in output order (CSR: first_output_, by_slot_).
    const auto outputs = program.output_slots();
    first_output_.assign(program.slot_count() + 1, 0);
    for (std::uint32_t s : outputs) ++first_output_[s + 1];
    for (std::size_t s = 0; s < program.slot_count(); ++s) first_output_[s + 1] += first_output_[s];
    by_slot_.resize(outputs.size());
    std::vector<std::size_t> next(first_output_.begin(), first_output_.end() - 1);
    for (std::size_t o = 0; o < outputs.size(); ++o) by_slot_[next[outputs[o]]++] = o;
  }

  std::vector<std::string> run() {
    std::vector<std::string> bodies(plan_.parts);
    auto ins = program_.instructions().begin();
    const auto end = program_.instructions().end();
    for (std::size_t p = 0; p < plan_.parts; ++p) {
      out_.clear();
      for (; ins != end && part_of(*ins) <= static_cast<int>(p); ++ins) print(*ins);
      assign_outputs(p);
      bodies[p] = std::move(out_);
      // Later parts read this part's values from the scratch array.
      for (std::uint32_t s : slots_of_part_[p]) {
        if (plan_.scratch_of[s] >= 0) operand_[s] = whole_[s] = fmt::format("{}[{}]", naming_.scratch, plan_.scratch_of[s]);
      }
    }
    return bodies;
  }

 private:
  // Loads belong to the part of whatever comes next: they print nothing.
  int part_of(const Instruction& ins) const {
    return is_load(ins) ? kNoPart : plan_.part_of_slot[ins.results[0]];
  }

  void print(const Instruction& ins) {
    const std::uint32_t r = ins.results[0];
    const OpcodeInfo& op = info(ins.op);
    // Only loads and pow print their constant ({2}); formatting a double is not free.
    const bool prints_constant = op.format.find("{2}") != std::string_view::npos;
    const std::string literal = prints_constant ? cpp_literal(ins.constant) : std::string();
    if (is_load(ins)) {  // loads print inline
      const std::string& name = ins.op == Opcode::Input ? naming_.inputs[ins.input] : literal;
      whole_[r].clear();
      append_format(whole_[r], op.format, {"", "", literal, name});
      const bool negative = ins.op == Opcode::Const && std::signbit(ins.constant);
      operand_[r] = negative ? "(" + whole_[r] + ")" : whole_[r];
      return;
    }
    // Views of the operands' texts: defining the results changes no operand's.
    std::array<std::string_view, 2> args{};
    for (int a = 0; a < op.arity; ++a) args[static_cast<std::size_t>(a)] = operand_[ins.args[a]];
    define(r, op.format, args, literal);
    if (op.results == 2) define(ins.results[1], op.format2, args, literal);
  }

  void define(std::uint32_t slot, std::string_view format, const std::array<std::string_view, 2>& args,
              const std::string& constant) {
    const std::string name = naming_.temporary_prefix + std::to_string(next_temporary_++);
    // indent "const" type name " = " value ";": appended, as fmt would print it.
    out_.append(declaration_).append(name).append(" = ");
    append_format(out_, format, {args[0], args[1], constant, ""});
    out_.append(";\n");
    if (plan_.scratch_of[slot] >= 0) {  // read by a later part
      out_.append(naming_.indent).append(naming_.scratch).append("[");
      out_.append(std::to_string(plan_.scratch_of[slot])).append("] = ").append(name).append(";\n");
    }
    operand_[slot] = whole_[slot] = name;
    if (!plan_.outputs_at_definition) return;
    for (std::size_t k = first_output_[slot]; k < first_output_[slot + 1]; ++k) {
      out_.append(naming_.indent).append(naming_.outputs[by_slot_[k]]).append(" = ").append(name).append(";\n");
    }
  }

  // The outputs of part p not yet assigned at their definition, in order; a constant run as one loop.
  void assign_outputs(std::size_t p) {
    std::size_t run_end = 0;  // outputs before it are assigned by a loop
    for (std::size_t i : outputs_of_part_[p]) {
      if (i < run_end) continue;
      const std::uint32_t slot = program_.output_slots()[i];
      if (plan_.outputs_at_definition && plan_.part_of_slot[slot] != kNoPart) continue;  // assigned at definition
      const std::string& value = whole_[slot];
      if (plan_.run_end[i] > i) {
        const auto [array, first] = array_of_output_[i];
        fmt::format_to(std::back_inserter(out_), "{}for (int i = {}; i < {}; ++i) {}[i] = {};\n", naming_.indent,
                       i - first, plan_.run_end[i] - first, *array, value);
        run_end = plan_.run_end[i];
        continue;
      }
      out_.append(naming_.indent).append(naming_.outputs[i]).append(" = ").append(value).append(";\n");
    }
  }

  const Program& program_;
  const CppNaming& naming_;
  const PartPlan& plan_;
  // What each slot reads as, in an operand position and as a whole statement's right side.
  std::vector<std::string> operand_;
  std::vector<std::string> whole_;
  const std::string declaration_;  // what every temporary's line starts with: "  const double "
  std::string out_;
  int next_temporary_ = 0;
  std::vector<std::vector<std::size_t>> outputs_of_part_;   // (parts) output indices, in order
  std::vector<std::vector<std::uint32_t>> slots_of_part_;   // (parts) slots each part computes
  std::vector<std::pair<const std::string*, std::size_t>> array_of_output_;  // name and first index of its array
  // outputs_at_definition: the outputs of slot s are by_slot_[first_output_[s] ... first_output_[s + 1] - 1].
  std::vector<std::size_t> first_output_;
  std::vector<std::size_t> by_slot_;
};

}  // namespace

CppParts emit_cpp_parts(const Program& program, const CppNaming& naming, std::size_t max_instructions,
                        std::size_t split_above) {
  if (naming.inputs.size() != program.input_count() || naming.outputs.size() != program.output_count()) {
    throw UsageError(fmt::format("emit_cpp: naming has {} inputs and {} outputs; the program has {} and {}",
                                 naming.inputs.size(), naming.outputs.size(), program.input_count(),
                                 program.output_count()));
  }
  std::size_t covered = 0;
  for (const auto& a : naming.output_arrays) covered += a.second;
  if (!naming.output_arrays.empty() && covered != program.output_count()) {
    throw UsageError(fmt::format("emit_cpp: naming's output arrays have {} elements; the program has {} outputs",
                                 covered, program.output_count()));
  }
  const PartPlan plan = plan_parts(program, naming, max_instructions, split_above);
  CppParts parts;
  parts.bodies = Printer(program, naming, plan).run();
  parts.scratch_size = plan.scratch_size;
  return parts;
}

std::string emit_cpp(const Program& program, const CppNaming& naming) {
  return std::move(emit_cpp_parts(program, naming, 0).bodies.front());
}

}  // namespace symdyn::symbolic
