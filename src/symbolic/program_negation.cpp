// Negations absorbed into the code that computes their operands.
//
// Why: lowering folds a sign into the sum that reads it, and the scheduler
// into the instruction computing the magnitude where it sees a free way
// (Scheduler::materialize), but only with what it has computed so far and
// without knowing who else reads the magnitude. A negation that remains (an
// output, a function's argument) can often go deeper once the whole program
// is known: -(x·y + z) = (-x)·y - z when -x is computed anyway (another
// output, say) and nothing else reads x·y or x·y + z. The rewritten
// instructions replace their originals one for one, the originals die, and
// the neg is saved.
//
// -v is free, that is computed by no instruction beyond those it replaces, when
//   - v is a constant (loads cost nothing), or v = -a (it is a);
//   - an instruction computes -v already: -v itself, or one of v's rewrites
//     below with a constant operand negated ((-c)·y for v = c·y), or b - a for
//     v = a - b;
//   - v is read by one instruction only, the one being rewritten, and a rule
//     below applies: a - b needs nothing, the others an operand whose
//     negation is free.
// Never longer, for any set of outputs (Program::subprogram, what an entry
// point of shared code runs): each rewrite drops a neg and adds at most one
// instruction, the computed -v it ends on, over operands that v's readers
// needed already.
#include <algorithm>
#include <optional>
#include <utility>

#include <symdyn/symbolic/detail/program_code.hpp>

namespace symdyn::symbolic::detail {
namespace {

// How -v, v = a ∘ b, is computed by one instruction of opcode `result`.
enum class Sign : std::uint8_t {
  Swap,     // result(b, a)
  Operand,  // result(-a, b) or result(a, -b)
  First,    // result(-a, b) or result(-b, a)
};

struct NegationRule {
  Opcode op;
  Opcode result;
  Sign sign;
};

// -(a - b) = b - a;  -(a·b) = (-a)·b = a·(-b);  -(a/b) = (-a)/b = a/(-b);
// -(a + b) = (-a) - b = (-b) - a.
constexpr NegationRule kNegationRules[] = {
    {Opcode::Sub, Opcode::Sub, Sign::Swap},
    {Opcode::Mul, Opcode::Mul, Sign::Operand},
    {Opcode::Div, Opcode::Div, Sign::Operand},
    {Opcode::Add, Opcode::Sub, Sign::First},
};

const NegationRule* rule_for(Opcode op) {
  const auto* it = std::find_if(std::begin(kNegationRules), std::end(kNegationRules),
                                [op](const NegationRule& r) { return r.op == op; });
  return it == std::end(kNegationRules) ? nullptr : it;
}

// The arguments of the rule's instruction computing -v, given the negated
// operand -v.args[i] as slot `negated` (i = 0 or 1; unused for Swap).
std::array<std::uint32_t, 2> rewritten_args(const NegationRule& rule,
                                            std::array<std::uint32_t, 2> args, std::size_t i,
                                            std::uint32_t negated) {
  switch (rule.sign) {
    case Sign::Swap:
      return {args[1], args[0]};
    case Sign::Operand:
      return i == 0 ? std::array{negated, args[1]} : std::array{args[0], negated};
    case Sign::First:
      return {negated, args[1 - i]};
  }
  return args;
}

class NegationAbsorber {
 public:
  NegationAbsorber(const CodeBuilder& code, std::span<const std::uint32_t> outputs)
      : old_(code),
        size_(static_cast<std::uint32_t>(code.size())),
        needed_(size_, false),
        readers_(size_, 0),
        negation_(size_, kNone),
        gain_(size_, kUnknown),
        built_(size_, kNone) {
    for (std::uint32_t s : outputs) {
      needed_[s] = true;
      ++readers_[s];
    }
    for (std::uint32_t k = size_; k-- > 0;) {
      if (!needed_[k]) continue;
      const Instruction& ins = old_[k];
      for (int a = 0; a < info(ins.op).arity; ++a) {
        needed_[ins.args[a]] = true;
        ++readers_[ins.args[a]];
      }
      if (ins.op == Opcode::Neg) negation_[ins.args[0]] = k;
    }
  }

  std::vector<Instruction> run(std::vector<std::uint32_t>& outputs) {
    for (std::uint32_t k = 0; k < size_; ++k) {
      if (needed_[k]) build(k);
    }
    for (std::uint32_t& s : outputs) s = built_[s];
    return std::move(new_.code());
  }

 private:
  static constexpr std::uint32_t kNone = ~0U;
  static constexpr int kMaxRewriteDepth = 256;
  static constexpr int kUnknown = -2;
  static constexpr int kNotFree = -1;

  // The new slot of old slot k, built on first demand (a computed negation
  // may be read before its place in the old order).
  std::uint32_t build(std::uint32_t k) {
    if (built_[k] != kNone) return built_[k];
    Instruction ins = old_[k];
    std::uint32_t slot = kNone;
    if (ins.op == Opcode::Neg) slot = absorbed(ins.args[0], k);
    if (slot == kNone) {
      for (int a = 0; a < info(ins.op).arity; ++a) ins.args[a] = build(ins.args[a]);
      slot = new_.emit(ins);
    }
    return built_[k] = slot;
  }

  // The new slot of -v computed without the neg `k`, or kNone.
  std::uint32_t absorbed(std::uint32_t v, std::uint32_t k) {
    if (const auto e = computed_negation(v, k)) return build(*e);
    if (readers_[v] == 1 && best_operand(v, 0).second != kNotFree) return rewrite(v);
    return kNone;
  }

  // An old needed slot computing -v, other than `except`.
  std::optional<std::uint32_t> computed_negation(std::uint32_t v, std::uint32_t except) const {
    const Instruction& ins = old_[v];
    if (ins.op == Opcode::Neg) return ins.args[0];
    if (negation_[v] != kNone && negation_[v] != except) return negation_[v];
    const NegationRule* rule = rule_for(ins.op);
    if (rule == nullptr) return std::nullopt;
    for (std::size_t i = 0; i < 2; ++i) {
      std::uint32_t negated = 0;
      if (rule->sign != Sign::Swap) {
        const Instruction& operand = old_[ins.args[i]];
        if (operand.op != Opcode::Const) continue;
        const auto c = old_.find(Opcode::Const, {}, -operand.constant);
        if (!c) continue;
        negated = *c;
      }
      const auto found = old_.find(rule->result, rewritten_args(*rule, ins.args, i, negated));
      if (found && needed_[*found]) return found;
    }
    return std::nullopt;
  }

  // What a free negation of v saves besides the neg it replaces: 1 when v,
  // read once, dies because its negation is computed already; 0 when it is
  // rewritten or a constant; kNotFree when it would cost an instruction.
  // Depth: rewrites down from the neg; a longer chain (a long sum,
  // binarized) is not followed, which bounds the recursion.
  int gain(std::uint32_t v, int depth) {
    if (gain_[v] == kUnknown) gain_[v] = static_cast<std::int8_t>(find_gain(v, depth));
    return gain_[v];
  }

  int find_gain(std::uint32_t v, int depth) {
    if (old_[v].op == Opcode::Const) return 0;
    if (computed_negation(v, kNone)) return readers_[v] == 1 ? 1 : 0;
    return readers_[v] == 1 ? best_operand(v, depth).second : kNotFree;
  }

  // The operand whose negation v's rule takes (the one saving most, the first
  // among equals) and what it saves; kNotFree when no rule applies.
  std::pair<std::size_t, int> best_operand(std::uint32_t v, int depth) {
    const NegationRule* rule = rule_for(old_[v].op);
    if (rule == nullptr || depth >= kMaxRewriteDepth) return {0, kNotFree};
    if (rule->sign == Sign::Swap) return {0, 0};
    const int first = gain(old_[v].args[0], depth + 1);
    const int second = gain(old_[v].args[1], depth + 1);
    return second > first ? std::pair{std::size_t{1}, second} : std::pair{std::size_t{0}, first};
  }

  // The new slot of -v, for a free v.
  std::uint32_t negated(std::uint32_t v) {
    const Instruction& ins = old_[v];
    if (ins.op == Opcode::Const) return new_.emit(Opcode::Const, {}, -ins.constant);
    if (const auto e = computed_negation(v, kNone)) return build(*e);
    return rewrite(v);
  }

  // -v by v's rule, v read once and its rule applying.
  std::uint32_t rewrite(std::uint32_t v) {
    const Instruction& ins = old_[v];
    const NegationRule& rule = *rule_for(ins.op);
    const std::size_t i = best_operand(v, 0).first;
    const std::uint32_t negated_operand = rule.sign == Sign::Swap ? 0 : negated(ins.args[i]);
    std::array<std::uint32_t, 2> args = ins.args;
    for (std::uint32_t& a : args) a = build(a);
    return new_.emit(rule.result, rewritten_args(rule, args, i, negated_operand));
  }

  const CodeBuilder& old_;
  std::uint32_t size_;
  std::vector<bool> needed_;             // (old slots) read by an output, directly or not
  std::vector<std::uint32_t> readers_;   // (old slots) reads by needed instructions and outputs
  std::vector<std::uint32_t> negation_;  // (old slots) the needed neg of it, or kNone
  std::vector<std::int8_t> gain_;        // (old slots) memo of gain, kUnknown until asked
  std::vector<std::uint32_t> built_;     // (old slots) its new slot, or kNone
  CodeBuilder new_;
};

}  // namespace

std::vector<Instruction> absorb_negations(const CodeBuilder& code,
                                          std::vector<std::uint32_t>& outputs) {
  NegationAbsorber absorber(code, outputs);
  return absorber.run(outputs);
}

}  // namespace symdyn::symbolic::detail
