#pragma once
// Private to the program compiler (program_*.cpp): the intermediate form
// between the expression DAG and the instructions.
//
// Why an intermediate form: signs, divisions and the operands of sums and
// products must be visible as a whole to fold negations, share reciprocals and
// find common operand pairs; instructions are binary and too late for that.
//
// The passes, in order:
//   lower               DAG -> IR: n-ary sums (signed terms) and products,
//                       powers lowered, signs pulled out of values
//   fold_reciprocals    divisions sharing a denominator -> multiplications by 1/d
//   extract_common_pairs  pair CSE over the sums and products
//   (program.cpp)       IR -> binary instructions, sincos fusion, slot numbering;
//                       between the two, absorb_negations (program_negation.cpp)

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <vector>

#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/program.hpp>

namespace symdyn::symbolic::ir {

// Hashing of the lowering and scheduling tables' keys: fold each field in with
// mix_hash, then finish_hash. (The tables are looked up, never iterated, so
// the hash never reaches the program.)
inline std::size_t mix_hash(std::size_t h, std::uint64_t v) {
  return (h ^ v) * 0x9e3779b97f4a7c15ULL;
}
inline std::size_t finish_hash(std::size_t h) {
  return h ^ (h >> 29);
}

enum class Op : std::uint8_t { Const, Input, Sum, Prod, Div, Neg, Sqrt, Pow, Call };

// An operand, or a value up to sign: node `id`, negated when `neg`.
struct Term {
  std::uint32_t id = 0;
  bool neg = false;
  friend auto operator<=>(const Term&, const Term&) = default;
};

// A node's operands, inline up to four: most nodes have one or two, and a
// graph has thousands of nodes, each of which used to allocate its list.
using Terms = detail::SmallVector<Term, 4>;

// Values are magnitudes: a Prod or a Div never carries a sign of its own (the
// sign travels in the Term that refers to it), only Sum terms and Neg do.
struct Node {
  Op op = Op::Const;
  Kind kind = Kind::Symbol;  // Call: the function kind
  Terms terms;               // Sum: signed terms; Prod: factors; Div: {numerator, denominator};
                             // Neg, Sqrt, Pow: {argument}; Call: arguments
  double constant = 0.0;     // Const: the value; Pow: the exponent
  std::uint32_t input = 0;   // Input: its index

  friend bool operator==(const Node&, const Node&) = default;

  static Node of(Op op, Terms terms = {}) {
    Node node;
    node.op = op;
    node.terms = std::move(terms);
    return node;
  }
};

class Graph {
 public:
  std::vector<Node> nodes;
  std::vector<Term> outputs;

  // Value numbering: returns the existing node equal to `node` (operands of
  // sums and products compared as multisets), or appends it.
  std::uint32_t intern(Node node);
  // Appends a node that no later intern will return (pair CSE's fresh pairs).
  std::uint32_t append(Node node);

  std::uint32_t constant(double value);
  // The node for a value up to sign, made positive: a negative constant is
  // loaded negative, anything else gets a Neg node.
  std::uint32_t materialize(Term value);

  // Which nodes the outputs need (indexed by node id).
  std::vector<char> live() const;  // bytes: much faster than bits

 private:
  static std::size_t hash(const Node& node);
  static bool same(const Node& a, const Node& b);
  void grow_index();
  // Node ids by hash, compared with the nodes themselves (no copy of their
  // operands): open addressing, each slot a node id + 1 (0: empty). Looked up,
  // never iterated: hashing cannot leak into the program. Only lowering and
  // fold_reciprocals intern, before any pass edits a node.
  std::vector<std::uint32_t> slots_;
  std::vector<std::size_t> hashes_;  // (by node id) the hash it was interned under; 0 if appended
  std::size_t indexed_ = 0;
};

// Throws UsageError for a bad input or definition list, or a symbol that is
// neither an input nor defined.
Graph lower(std::span<const Expr> inputs, std::span<const Expr> outputs,
            std::span<const Definition> definitions);
void fold_reciprocals(Graph& graph);
// Among pairs of equally many holders, pair CSE extracts first the one of
// the smallest key, or (ExistingFirst) the one with the most holders that are
// the pair itself, then the smallest key. Neither makes every program shorter
// than the other: compile_program tries both.
enum class PairTies : std::uint8_t { ByKey, ExistingFirst };
// Both at once: `graph` gets ExistingFirst's pairs; the result is the graph
// ByKey makes, where the two would choose another pair at some step (nothing
// where they agree throughout: the same graph).
std::optional<Graph> extract_common_pairs(Graph& graph);

// Sums and products with more operands take no part in pair CSE.
inline constexpr std::size_t kMaxPairOperands = 128;

}  // namespace symdyn::symbolic::ir
