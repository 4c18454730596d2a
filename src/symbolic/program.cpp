// IR -> instructions: binarization with sign folding, sincos fusion, slot
// numbering and workspace allocation; the opcode table and operation counts.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

#include <symdyn/symbolic/detail/program_code.hpp>
#include <symdyn/symbolic/detail/program_ir.hpp>
#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/program.hpp>

namespace symdyn::symbolic {
namespace {

#define SYMDYN_CALL_FORMAT_1 "({0})"
#define SYMDYN_CALL_FORMAT_2 "({0}, {1})"

constexpr OpcodeInfo kOpcodes[] = {
#define SYMDYN_CORE_INFO(op, name, arity, results, format, format2, counted) \
  {name, arity, results, format, format2, false, Kind::Symbol},
    SYMDYN_FOR_EACH_CORE_OPCODE(SYMDYN_CORE_INFO)
#undef SYMDYN_CORE_INFO
#define SYMDYN_CALL_INFO(kind, name, arity, cpp, cost) \
  {name, arity, 1, cpp SYMDYN_CALL_FORMAT_##arity, "", true, Kind::kind},
        SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_CALL_INFO)
#undef SYMDYN_CALL_INFO
};

constexpr Kind kFunctionKinds[] = {
#define SYMDYN_FUNCTION_KIND(kind, ...) Kind::kind,
    SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_FUNCTION_KIND)
#undef SYMDYN_FUNCTION_KIND
};

// The table's `counted as` column names a field; loads name `none`.
struct CountFields : OperationCount {
  int none = 0;
};

int CountFields::*counted_field(Opcode op) {
  switch (op) {
#define SYMDYN_COUNTED(op, name, arity, results, format, format2, counted) \
  case Opcode::op:                                                         \
    return &CountFields::counted;
    SYMDYN_FOR_EACH_CORE_OPCODE(SYMDYN_COUNTED)
#undef SYMDYN_COUNTED
    default:
      return nullptr;  // calls, counted per kind
  }
}

// Weights of OperationCount::weighted (relative to a multiply).
constexpr int kDivWeight = 4;
constexpr int kSqrtWeight = 4;
constexpr int kPowWeight = 16;
constexpr int kSinCosWeight = 15;

std::size_t function_index(Kind kind) {
  const auto* it = std::find(std::begin(kFunctionKinds), std::end(kFunctionKinds), kind);
  if (it == std::end(kFunctionKinds)) {
    throw UsageError(fmt::format("OperationCount: '{}' is not a function kind", info(kind).name));
  }
  return static_cast<std::size_t>(it - std::begin(kFunctionKinds));
}

Opcode call_opcode(Kind kind) {
  for (std::size_t i = 0; i < std::size(kOpcodes); ++i) {
    if (kOpcodes[i].is_call && kOpcodes[i].kind == kind) return static_cast<Opcode>(i);
  }
  throw UsageError(fmt::format("compile_program: no opcode for '{}'", info(kind).name));
}

// Builds instructions from the IR, one value-numbered instruction per distinct
// (opcode, operands, payload). Instruction k defines slot k.
class Scheduler {
 public:
  explicit Scheduler(const ir::Graph& graph) : g_(graph), resolved_(graph.nodes.size()) {
    code_.reserve(2 *
                  graph.nodes.size());  // binarized n-ary nodes make more instructions than nodes
  }

  // The slots of the outputs, in order, except that negated products and
  // sums come last: the negations made before them (-(c·x) = (-c)·x among
  // them) may take their signs, -(c·x·y) = ((-c)·x)·y.
  std::vector<std::uint32_t> outputs(std::span<const ir::Term> terms) {
    std::vector<std::uint32_t> slots(terms.size());
    std::vector<std::pair<std::size_t, ir::Term>> deferred;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      const ir::Term r = resolve(terms[i].id);
      const ir::Term v{r.id, r.neg != terms[i].neg};
      const Opcode op = code_[v.id].op;
      if (v.neg && (op == Opcode::Mul || op == Opcode::Add) && !scaled_by_constant(v) &&
          !shifted_by_constant(v)) {
        deferred.emplace_back(i, v);
      } else {
        slots[i] = materialize(v);
      }
    }
    for (const auto& [i, v] : deferred) slots[i] = materialize(v);
    return slots;
  }
  const detail::CodeBuilder& code() const { return code_; }

 private:
  // The value of an IR node up to sign, its operands first (post-order).
  ir::Term resolve(std::uint32_t root) {
    std::vector<std::pair<std::uint32_t, bool>>& stack = stack_;
    stack.emplace_back(root, false);
    while (!stack.empty()) {
      auto& [id, expanded] = stack.back();
      if (resolved_[id]) {
        stack.pop_back();
      } else if (!expanded) {
        expanded = true;
        const std::uint32_t node = id;
        const auto& terms = g_.nodes[node].terms;
        for (std::size_t k = terms.size(); k-- > 0;) {  // the first operand on top
          if (!resolved_[terms[k].id]) stack.emplace_back(terms[k].id, false);
        }
      } else {
        const std::uint32_t node = id;
        stack.pop_back();
        resolved_[node] = build(g_.nodes[node]);
      }
    }
    return *resolved_[root];
  }

  // The operand's resolved value, with the operand's own sign applied.
  ir::Term operand(ir::Term t) const {
    const ir::Term r = *resolved_[t.id];
    return {r.id, r.neg != t.neg};
  }

  ir::Term build(const ir::Node& node) {
    switch (node.op) {
      case ir::Op::Const:
        return {emit(Opcode::Const, {}, node.constant), false};
      case ir::Op::Input: {
        Instruction ins;
        ins.op = Opcode::Input;
        ins.input = node.input;
        return {emit(ins), false};
      }
      case ir::Op::Sum:
        return build_sum(node);
      case ir::Op::Prod:
        return build_product(node);
      case ir::Op::Div: {
        const ir::Term num = operand(node.terms[0]);
        const ir::Term den = operand(node.terms[1]);
        return {emit(Opcode::Div, {num.id, den.id}), num.neg != den.neg};
      }
      case ir::Op::Neg: {
        const ir::Term a = operand(node.terms[0]);
        return {a.id, !a.neg};
      }
      case ir::Op::Sqrt:
        return {emit(Opcode::Sqrt, {materialize(operand(node.terms[0]))}), false};
      case ir::Op::Pow:
        return {emit(Opcode::Pow, {materialize(operand(node.terms[0]))}, node.constant), false};
      case ir::Op::Call: {
        std::array<std::uint32_t, 2> args{};
        for (std::size_t i = 0; i < node.terms.size(); ++i)
          args[i] = materialize(operand(node.terms[i]));
        return {emit(call_opcode(node.kind), args), false};
      }
    }
    throw UsageError("compile_program: unknown IR node");
  }

  // p1 + p2 + ... - n1 - n2 ...; with no positive term, -(n1 + n2 + ...).
  ir::Term build_sum(const ir::Node& node) {
    detail::SmallVector<std::uint32_t, 16> positive;
    detail::SmallVector<std::uint32_t, 16> negative;
    for (ir::Term t : node.terms) {
      const ir::Term v = operand(t);
      (v.neg ? negative : positive).push_back(v.id);
    }
    if (positive.empty()) return {chain(Opcode::Add, negative), true};
    std::uint32_t acc = chain(Opcode::Add, positive);
    for (std::uint32_t n : negative) acc = emit(Opcode::Sub, {acc, n});
    return {acc, false};
  }

  ir::Term build_product(const ir::Node& node) {
    bool neg = false;
    detail::SmallVector<std::uint32_t, 16> factors;
    for (ir::Term t : node.terms) {
      const ir::Term v = operand(t);
      neg = neg != v.neg;
      factors.push_back(v.id);
    }
    return {chain(Opcode::Mul, factors), neg};
  }

  std::uint32_t chain(Opcode op, std::span<const std::uint32_t> values) {
    std::uint32_t acc = values[0];
    for (std::size_t i = 1; i < values.size(); ++i) acc = emit(op, {acc, values[i]});
    return acc;
  }

  // The value v, negated if v.neg. The sign goes into the instruction that
  // computes the magnitude where that costs no more than a negation:
  // -(a - b) = b - a, -(c·x) = (-c)·x, -(c + x) = (-c) - x, and -(a·b) = (-a)·b
  // and -(a + b) = (-a) - b when -a is computed already. Where nothing else reads the magnitude,
  // finalize drops it, and the negation is saved.
  std::uint32_t materialize(ir::Term v) {
    if (!v.neg) return v.id;
    const Instruction ins = code_[v.id];
    const auto [a, b] = ins.args;
    switch (ins.op) {
      case Opcode::Const:
        return emit(Opcode::Const, {}, -ins.constant);
      case Opcode::Sub:
        return emit(Opcode::Sub, {b, a});
      case Opcode::Mul:
        if (code_[a].op == Opcode::Const)
          return emit(Opcode::Mul, {emit(Opcode::Const, {}, -code_[a].constant), b});
        if (const auto na = existing_negation(a)) return emit(Opcode::Mul, {*na, b});
        if (const auto nb = existing_negation(b)) return emit(Opcode::Mul, {a, *nb});
        break;
      case Opcode::Add:
        if (code_[a].op == Opcode::Const)
          return emit(Opcode::Sub, {emit(Opcode::Const, {}, -code_[a].constant), b});
        if (const auto na = existing_negation(a)) return emit(Opcode::Sub, {*na, b});
        if (const auto nb = existing_negation(b)) return emit(Opcode::Sub, {*nb, a});
        break;
      default:
        break;
    }
    return emit(Opcode::Neg, {v.id});
  }

  bool shifted_by_constant(ir::Term v) const {
    return v.neg && code_[v.id].op == Opcode::Add && code_[code_[v.id].args[0]].op == Opcode::Const;
  }

  bool scaled_by_constant(ir::Term v) const {
    return v.neg && code_[v.id].op == Opcode::Mul && code_[code_[v.id].args[0]].op == Opcode::Const;
  }

  // The slot of -x if an instruction computes it already: -x itself, or
  // (-c)·y for x = c·y.
  std::optional<std::uint32_t> existing_negation(std::uint32_t x) const {
    const Instruction& ins = code_[x];
    if (ins.op == Opcode::Mul && code_[ins.args[0]].op == Opcode::Const) {
      const auto c = existing(Opcode::Const, {}, -code_[ins.args[0]].constant);
      return c ? existing(Opcode::Mul, {*c, ins.args[1]}) : std::nullopt;
    }
    return existing(Opcode::Neg, {x, 0});
  }

  std::optional<std::uint32_t> existing(Opcode op, std::array<std::uint32_t, 2> args,
                                        double constant = 0.0) const {
    return code_.find(op, args, constant);
  }
  std::uint32_t emit(Opcode op, std::array<std::uint32_t, 2> args, double constant = 0.0) {
    return code_.emit(op, args, constant);
  }
  std::uint32_t emit(const Instruction& ins) { return code_.emit(ins); }

  const ir::Graph& g_;
  std::vector<std::optional<ir::Term>> resolved_;  // by IR node id
  std::vector<std::pair<std::uint32_t, bool>>
      stack_;                 // resolve's: (node, operands pushed), empty between calls
  detail::CodeBuilder code_;  // every instruction value-numbered
};

// Drops what no output needs, fuses sin and cos of one argument into sincos
// (at the place of the first), and renumbers the slots in schedule order.
// `code` defines slot k at instruction k; `outputs` are slots of it.
std::vector<Instruction> finalize(const std::vector<Instruction>& code,
                                  std::vector<std::uint32_t>& outputs, std::uint32_t* slot_count) {
  std::vector<char> needed(code.size(), 0);  // bytes: read and set much faster than bits
  for (std::uint32_t s : outputs) needed[s] = true;
  for (std::size_t k = code.size(); k-- > 0;) {
    if (!needed[k]) continue;
    for (int a = 0; a < info(code[k].op).arity; ++a) needed[code[k].args[a]] = true;
  }
  // The sin and cos of each argument slot, if both are needed.
  std::map<std::uint32_t, std::pair<std::uint32_t, std::uint32_t>> trig;  // argument -> (sin, cos)
  constexpr std::uint32_t kNone = ~0U;
  for (std::uint32_t k = 0; k < code.size(); ++k) {
    const Opcode op = code[k].op;
    if (!needed[k] || (op != Opcode::Sin && op != Opcode::Cos)) continue;
    auto [it, inserted] = trig.try_emplace(code[k].args[0], kNone, kNone);
    (op == Opcode::Sin ? it->second.first : it->second.second) = k;
  }
  std::vector<std::uint32_t> renamed(code.size(), kNone);
  std::vector<Instruction> out;
  out.reserve(code.size());
  std::uint32_t next = 0;
  for (std::uint32_t k = 0; k < code.size(); ++k) {
    if (!needed[k]) continue;
    Instruction ins = code[k];
    for (int a = 0; a < info(ins.op).arity; ++a) ins.args[a] = renamed[ins.args[a]];
    if (ins.op == Opcode::Sin || ins.op == Opcode::Cos) {
      const auto [sine, cosine] = trig.at(code[k].args[0]);
      if (sine != kNone && cosine != kNone) {
        if (renamed[k] != kNone) continue;  // fused into the sincos of its partner
        ins.op = Opcode::SinCos;
        renamed[sine] = next++;
        renamed[cosine] = next++;
        ins.results = {renamed[sine], renamed[cosine]};
        out.push_back(ins);
        continue;
      }
    }
    renamed[k] = next++;
    ins.results = {renamed[k], 0};
    out.push_back(ins);
  }
  for (std::uint32_t& s : outputs) s = renamed[s];
  *slot_count = next;
  return out;
}

// Workspace slots reused by liveness: a slot is freed after its last reader
// runs (outputs live to the end); results never share a slot with their own
// arguments, so an instruction may read all its arguments after writing.
struct Allocation {
  std::vector<Instruction> code;
  std::vector<std::uint32_t> outputs;
  std::size_t size = 0;
};

Allocation allocate(const std::vector<Instruction>& code, const std::vector<std::uint32_t>& outputs,
                    std::uint32_t slot_count) {
  constexpr std::size_t kNever = ~std::size_t{0};
  constexpr std::size_t kEnd = kNever - 1;
  std::vector<std::size_t> last_use(slot_count, kNever);
  for (std::size_t k = 0; k < code.size(); ++k) {
    for (int a = 0; a < info(code[k].op).arity; ++a) last_use[code[k].args[a]] = k;
  }
  for (std::uint32_t s : outputs) last_use[s] = kEnd;

  Allocation result;
  result.code.reserve(code.size());
  std::vector<std::uint32_t> where(slot_count, 0);
  std::vector<std::uint32_t> free;
  auto take = [&]() {
    if (free.empty()) return static_cast<std::uint32_t>(result.size++);
    const std::uint32_t w = free.back();
    free.pop_back();
    return w;
  };
  for (std::size_t k = 0; k < code.size(); ++k) {
    Instruction ins = code[k];
    const int arity = info(ins.op).arity;
    for (int a = 0; a < arity; ++a) ins.args[a] = where[code[k].args[a]];
    for (int r = 0; r < info(ins.op).results; ++r)
      ins.results[r] = where[code[k].results[r]] = take();
    for (int a = 0; a < arity; ++a) {
      const std::uint32_t s = code[k].args[a];
      const bool repeated = a == 1 && code[k].args[0] == s;
      if (last_use[s] == k && !repeated) free.push_back(where[s]);
    }
    for (int r = 0; r < info(ins.op).results; ++r) {
      if (last_use[code[k].results[r]] == kNever) free.push_back(ins.results[r]);
    }
    result.code.push_back(ins);
  }
  for (std::uint32_t s : outputs) result.outputs.push_back(where[s]);
  return result;
}

// A program's instructions (finalized: dead code dropped, sincos fused) and
// output slots.
struct Scheduled {
  std::vector<Instruction> code;
  std::vector<std::uint32_t> outputs;
  std::uint32_t slot_count = 0;
};

Scheduled schedule(const ir::Graph& graph) {
  Scheduler scheduler(graph);
  Scheduled s;
  s.outputs = scheduler.outputs(graph.outputs);
  const std::vector<Instruction> code = detail::absorb_negations(scheduler.code(), s.outputs);
  s.code = finalize(code, s.outputs, &s.slot_count);
  return s;
}

// The operations that computing some of the outputs executes (what
// Program::subprogram(outputs, ...).operation_count().total() counts).
int operations(const Scheduled& s, std::span<const std::size_t> outputs) {
  std::vector<char> needed(s.slot_count, 0);
  for (std::size_t o : outputs) needed[s.outputs[o]] = true;
  int count = 0;
  for (std::size_t k = s.code.size(); k-- > 0;) {
    const Instruction& ins = s.code[k];
    const OpcodeInfo& op = info(ins.op);
    if (!needed[ins.results[0]] && !(op.results == 2 && needed[ins.results[1]])) continue;
    count += ins.op != Opcode::Const && ins.op != Opcode::Input ? 1 : 0;
    for (int a = 0; a < op.arity; ++a) needed[ins.args[a]] = true;
  }
  return count;
}

}  // namespace

const OpcodeInfo& info(Opcode op) {
  return kOpcodes[static_cast<std::size_t>(op)];
}

Program compile_program(std::span<const Expr> inputs, std::span<const Expr> outputs,
                        std::span<const Definition> definitions,
                        std::span<const std::vector<std::size_t>> groups) {
  std::vector<std::size_t> all;
  if (groups.empty()) {
    for (std::size_t i = 0; i < outputs.size(); ++i) all.push_back(i);
    groups = std::span(&all, 1);
  }
  for (const std::vector<std::size_t>& group : groups) {
    for (std::size_t o : group) {
      if (o >= outputs.size()) {
        throw UsageError(
            fmt::format("compile_program: a group names output {} of {}", o, outputs.size()));
      }
    }
  }
  ir::Graph existing_first = ir::lower(inputs, outputs, definitions);
  ir::fold_reciprocals(existing_first);
  const std::optional<ir::Graph> by_key = ir::extract_common_pairs(existing_first);
  Scheduled chosen = schedule(by_key ? *by_key : existing_first);
  if (by_key) {  // the ties changed something
    Scheduled other = schedule(existing_first);
    auto longer = [&](const auto& group) {
      return operations(other, group) > operations(chosen, group);
    };
    auto shorter = [&](const auto& group) {
      return operations(other, group) < operations(chosen, group);
    };
    if (std::none_of(groups.begin(), groups.end(), longer) &&
        std::any_of(groups.begin(), groups.end(), shorter)) {
      chosen = std::move(other);
    }
  }

  Program program;
  program.input_count_ = inputs.size();
  program.instructions_ = std::move(chosen.code);
  program.slot_count_ = chosen.slot_count;
  program.outputs_ = std::move(chosen.outputs);
  program.allocate_workspace();
  return program;
}

void Program::allocate_workspace() {
  Allocation allocation =
      allocate(instructions_, outputs_, static_cast<std::uint32_t>(slot_count_));
  exec_ = std::move(allocation.code);
  exec_outputs_ = std::move(allocation.outputs);
  workspace_size_ = allocation.size;
}

Program Program::subprogram(std::span<const std::size_t> outputs,
                            std::span<const std::size_t> inputs) const {
  constexpr std::uint32_t kNone = ~0U;
  std::vector<std::uint32_t> input_index(input_count_, kNone);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i] >= input_count_)
      throw UsageError(fmt::format("subprogram: no input {}", inputs[i]));
    input_index[inputs[i]] = static_cast<std::uint32_t>(i);
  }
  std::vector<char> needed(slot_count_, 0);  // bytes: read and set much faster than bits
  for (std::size_t o : outputs) {
    if (o >= outputs_.size()) throw UsageError(fmt::format("subprogram: no output {}", o));
    needed[outputs_[o]] = true;
  }
  std::size_t kept = 0;
  for (std::size_t k = instructions_.size(); k-- > 0;) {
    const Instruction& ins = instructions_[k];
    const int results = info(ins.op).results;
    if (!needed[ins.results[0]] && !(results == 2 && needed[ins.results[1]])) continue;
    ++kept;
    for (int a = 0; a < info(ins.op).arity; ++a) needed[ins.args[a]] = true;
  }
  Program sub;
  sub.input_count_ = inputs.size();
  sub.instructions_.reserve(kept);
  std::vector<std::uint32_t> renamed(slot_count_, kNone);
  std::uint32_t next = 0;
  for (const Instruction& ins : instructions_) {
    const int results = info(ins.op).results;
    if (!needed[ins.results[0]] && !(results == 2 && needed[ins.results[1]])) continue;
    Instruction copy = ins;
    for (int a = 0; a < info(ins.op).arity; ++a) copy.args[a] = renamed[ins.args[a]];
    for (int r = 0; r < results; ++r) copy.results[r] = renamed[ins.results[r]] = next++;
    if (ins.op == Opcode::Input) {
      if (input_index[ins.input] == kNone) {
        throw UsageError(
            fmt::format("subprogram: the outputs need input {}, which is not given", ins.input));
      }
      copy.input = input_index[ins.input];
    }
    sub.instructions_.push_back(copy);
  }
  for (std::size_t o : outputs) sub.outputs_.push_back(renamed[outputs_[o]]);
  sub.slot_count_ = next;
  sub.allocate_workspace();
  return sub;
}

void Program::check_sizes(std::size_t inputs, std::size_t outputs, std::size_t workspace) const {
  if (inputs != input_count_ || outputs != outputs_.size() || workspace < workspace_size_) {
    throw UsageError(
        fmt::format("Program::run: given {} inputs, {} outputs, a workspace of {}; the program "
                    "needs {}, {}, at least {}",
                    inputs, outputs, workspace, input_count_, outputs_.size(), workspace_size_));
  }
}

OperationCount Program::operation_count() const {
  CountFields count;
  for (const Instruction& ins : instructions_) {
    const OpcodeInfo& op = info(ins.op);
    if (op.is_call) {
      ++count.call(op.kind);
    } else {
      ++(count.*counted_field(ins.op));
    }
  }
  return static_cast<OperationCount>(count);
}

int& OperationCount::call(Kind kind) {
  return calls[function_index(kind)];
}
int OperationCount::call(Kind kind) const {
  return calls[function_index(kind)];
}

int OperationCount::total() const {
  int n = add + mul + div + neg + sqrt + pow + sincos;
  for (int c : calls) n += c;
  return n;
}

int OperationCount::weighted() const {
  int w = add + mul + neg + kDivWeight * div + kSqrtWeight * sqrt + kPowWeight * pow +
          kSinCosWeight * sincos;
  for (std::size_t i = 0; i < calls.size(); ++i) w += calls[i] * info(kFunctionKinds[i]).cost;
  return w;
}

std::string OperationCount::str() const {
  std::vector<std::string> parts;
  auto put = [&](int n, std::string_view name) {
    if (n != 0) parts.push_back(fmt::format("{} {}", n, name));
  };
  put(add, "add");
  put(mul, "mul");
  put(div, "div");
  put(neg, "neg");
  put(sqrt, "sqrt");
  put(pow, "pow");
  put(sincos, "sincos");
  for (std::size_t i = 0; i < calls.size(); ++i) put(calls[i], info(kFunctionKinds[i]).name);
  return parts.empty() ? "nothing" : fmt::format("{}", fmt::join(parts, ", "));
}

std::string to_string(const Program& program) {
  std::string out;
  for (const Instruction& ins : program.instructions()) {
    const OpcodeInfo& op = info(ins.op);
    out += fmt::format("s{}", ins.results[0]);
    if (op.results == 2) out += fmt::format(", s{}", ins.results[1]);
    out += fmt::format(" = {}", op.name);
    for (int a = 0; a < op.arity; ++a) out += fmt::format(" s{}", ins.args[a]);
    if (ins.op == Opcode::Const || ins.op == Opcode::Pow) out += fmt::format(" {}", ins.constant);
    if (ins.op == Opcode::Input) out += fmt::format(" {}", ins.input);
    out += '\n';
  }
  for (std::size_t i = 0; i < program.output_count(); ++i) {
    out += fmt::format("out {} = s{}\n", i, program.output_slots()[i]);
  }
  return out;
}

}  // namespace symdyn::symbolic
