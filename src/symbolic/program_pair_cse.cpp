// Pair CSE: operand pairs shared by several sums (or products) computed once.
//
// Why: interning shares equal nodes, but a + b + c and a + b + d are distinct
// sums that both compute a + b when binarized. The classic greedy cure counts,
// for every unordered pair of operands, how many n-ary nodes contain it;
// extracts the most frequent pair p = a ∘ b into a node of its own; replaces
// it by p in each holder; and repeats while some pair has two holders or more.
// Each extraction saves (holders - 1) operations and shrinks the holders, so
// the loop ends. Counts are updated incrementally: removing or adding an
// operand touches only the pairs it belongs to.
//
// In sums, operands carry signs. The pair {±a, ±b} is keyed by its operands and
// whether their signs differ: {+a, -b} and {-a, +b} are both ±(a - b), and
// {+a, +b} and {-a, -b} both ±(a + b). The extracted node is a + b or a - b (a
// the operand created first) and replaces the pair with the sign a had there.
#include <algorithm>
#include <map>
#include <set>

#include "symbolic/program_ir.hpp"

namespace symdyn::symbolic::ir {
namespace {

struct PairKey {
  Op op = Op::Sum;
  std::uint32_t lo = 0;
  std::uint32_t hi = 0;
  bool differ = false;  // sums: the two signs differ
  friend auto operator<=>(const PairKey&, const PairKey&) = default;
};

PairKey key_of(Op op, Term a, Term b) {
  if (b.id < a.id) std::swap(a, b);
  return {op, a.id, b.id, op == Op::Sum && a.neg != b.neg};
}

class PairTable {
 public:
  explicit PairTable(Graph& graph) : g_(graph) {}

  void add_holder(std::uint32_t node) {
    const std::vector<Term>& terms = g_.nodes[node].terms;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      for (std::size_t j = i + 1; j < terms.size(); ++j) count(key_of(g_.nodes[node].op, terms[i], terms[j]), node, +1);
    }
  }

  // Extracts the pair with the most holders (the smallest key among equals).
  // Returns false when no pair has two holders.
  bool extract_best() {
    if (ranked_.empty()) return false;
    const PairKey key = ranked_.begin()->second;
    const std::uint32_t pair = g_.append(Node::of(key.op, {{key.lo, false}, {key.hi, key.differ}}));
    std::vector<std::uint32_t> holders;
    for (const auto& [node, multiplicity] : holders_.at(key)) holders.push_back(node);
    for (std::uint32_t node : holders) {
      std::size_t i = 0;
      std::size_t j = 0;
      while (find(node, key, &i, &j)) {
        const bool sign = g_.nodes[node].terms[i].neg;
        remove_term(node, std::max(i, j));
        remove_term(node, std::min(i, j));
        add_term(node, {pair, sign});
      }
    }
    return true;
  }

 private:
  // Positions i != j of the pair's operands in node (with matching signs).
  bool find(std::uint32_t node, const PairKey& key, std::size_t* i, std::size_t* j) const {
    const std::vector<Term>& terms = g_.nodes[node].terms;
    for (std::size_t a = 0; a < terms.size(); ++a) {
      if (terms[a].id != key.lo) continue;
      for (std::size_t b = 0; b < terms.size(); ++b) {
        if (b == a || terms[b].id != key.hi) continue;
        if (key.op == Op::Sum && (terms[a].neg != terms[b].neg) != key.differ) continue;
        *i = a;
        *j = b;
        return true;
      }
    }
    return false;
  }

  void remove_term(std::uint32_t node, std::size_t position) {
    std::vector<Term>& terms = g_.nodes[node].terms;
    for (std::size_t q = 0; q < terms.size(); ++q) {
      if (q != position) count(key_of(g_.nodes[node].op, terms[position], terms[q]), node, -1);
    }
    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(position));
  }

  void add_term(std::uint32_t node, Term t) {
    std::vector<Term>& terms = g_.nodes[node].terms;
    for (Term other : terms) count(key_of(g_.nodes[node].op, t, other), node, +1);
    terms.push_back(t);
  }

  // Adds delta to the number of times node holds the pair, keeping `ranked_`
  // in step with the number of distinct holders.
  void count(const PairKey& key, std::uint32_t node, int delta) {
    auto& holders = holders_[key];
    const auto before = static_cast<int>(holders.size());
    if ((holders[node] += delta) == 0) holders.erase(node);
    const auto after = static_cast<int>(holders.size());
    if (before != after) {
      if (before >= 2) ranked_.erase({-before, key});
      if (after >= 2) ranked_.insert({-after, key});
    }
    if (holders.empty()) holders_.erase(key);
  }

  Graph& g_;
  std::map<PairKey, std::map<std::uint32_t, int>> holders_;  // pair -> node -> times held
  std::set<std::pair<int, PairKey>> ranked_;                  // (-holders, pair), holders >= 2
};

}  // namespace

void extract_common_pairs(Graph& graph) {
  const std::vector<bool> live = graph.live();
  PairTable table(graph);
  for (std::uint32_t id = 0; id < live.size(); ++id) {
    const Node& node = graph.nodes[id];
    const bool nary = node.op == Op::Sum || node.op == Op::Prod;
    if (live[id] && nary && node.terms.size() <= kMaxPairOperands) table.add_holder(id);
  }
  while (table.extract_best()) {
  }
}

}  // namespace symdyn::symbolic::ir
