// Pair CSE: operand pairs shared by several sums (or products) computed once.
//
// Why: interning shares equal nodes, but a + b + c and a + b + d are distinct
// sums that both compute a + b when binarized. The classic greedy cure counts,
// for every unordered pair of operands, how many n-ary nodes contain it;
// extracts the most frequent pair p = a ∘ b into a node of its own; replaces
// it by p in each holder; and repeats while some pair has two holders or more.
// Each extraction saves (holders - 1) operations and shrinks the holders, so
// the loop ends. Counts are updated incrementally: removing or adding an
// operand touches only the pairs it belongs to. Among equally frequent pairs,
// the smallest key goes first, or (PairTies::ExistingFirst) the pair held by
// the most nodes that are that pair alone, a sum or product of two operands.
//
// In sums, operands carry signs. The pair {±a, ±b} is keyed by its operands and
// whether their signs differ: {+a, -b} and {-a, +b} are both ±(a - b), and
// {+a, +b} and {-a, -b} both ±(a + b). The extracted node is a + b or a - b (a
// the operand created first) and replaces the pair with the sign a had there.
//
// The tables. A pair is a 64-bit key whose integer order is the order of
// (op, lo, hi, differ), so "the smallest key among equals" is an integer
// comparison. A pair of two operands of the input can only lose holders (a
// node gains operands only as fresh pairs are extracted), so a pair with one
// holder after the initial count is never extracted and is not tracked
// further; tracked pairs (the others, and every pair with a fresh operand)
// keep their holders, with the times each holds them, in a vector sorted by
// node. A max-heap of (holders, exact holders, pair) is kept lazily: every
// tracked pair with two holders or more has an entry whose counts are at
// least its own (a holder becomes exact, two operands, only by gaining a
// fresh pair, whose count then rises). Pairs whose count rose during an
// extraction push one entry each at its end; counts that fall push nothing,
// and an entry found on top with counts above the pair's is replaced then by
// one with the right counts.
//
// Both orders at once: the state after each extraction depends only on the
// pairs extracted so far, not on the order that chose them. A run by
// ExistingFirst keeps a second heap, by key, fed the same entries; while
// both heaps name the same pair on top, a run by key would be the same run.
// Where they first differ, the table and the graph are copied and the copy
// goes on by key.
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <queue>
#include <stdexcept>

#include <symdyn/symbolic/detail/flat_map.hpp>
#include <symdyn/symbolic/detail/program_ir.hpp>
#include <symdyn/symbolic/detail/small_vector.hpp>

namespace symdyn::symbolic::ir {
namespace {

// Operand ids take 31 bits each in a pair key.
constexpr std::uint32_t kMaxPairOperandId = (1U << 31) - 1;

// (op, lo, hi, differ) packed so that integer order is lexicographic order:
// op (Sum before Prod) in bit 63, lo in bits 62..32, hi in bits 31..1, differ in bit 0.
std::uint64_t key_of(Op op, Term a, Term b) {
  if (b.id < a.id) std::swap(a, b);
  const bool differ = op == Op::Sum && a.neg != b.neg;
  return (std::uint64_t{op == Op::Prod} << 63) | (std::uint64_t{a.id} << 32) |
         (std::uint64_t{b.id} << 1) | std::uint64_t{differ};
}
Op op_of(std::uint64_t key) {
  return (key >> 63) != 0 ? Op::Prod : Op::Sum;
}
std::uint32_t lo_of(std::uint64_t key) {
  return static_cast<std::uint32_t>(key >> 32) & kMaxPairOperandId;
}
std::uint32_t hi_of(std::uint64_t key) {
  return static_cast<std::uint32_t>(key >> 1) & kMaxPairOperandId;
}
bool differ_of(std::uint64_t key) {
  return (key & 1U) != 0;
}

class PairTable {
 public:
  // `pairs`: how many the holders have at first (the index grows past it as pairs are extracted).
  // watch_by_key (with ExistingFirst): also follow what ties by key would choose, see fork().
  PairTable(Graph& graph, PairTies ties, std::size_t pairs, bool watch_by_key = false)
      : g_(&graph),
        ties_(ties),
        watching_(watch_by_key && ties == PairTies::ExistingFirst),
        index_(pairs) {}

  // Counts the pairs of a holder. Before rank(); holders in increasing order.
  void add_holder(std::uint32_t node) {
    holder_nodes_.push_back(node);
    for_each_pair(node, [&](std::uint64_t key) {
      const std::uint32_t id = id_of(key);
      enumerated_.push_back(id);
      InitialCount& c = initial_[id];
      if (c.last_holder != node) {
        c.last_holder = node;
        ++c.holders;
      }
    });
  }

  // Tracks the pairs with two holders or more, and ranks them.
  void rank() {
    record_of_.assign(initial_.size(), kNone);
    std::size_t next =
        0;  // in enumerated_: the pairs of each holder, in the order add_holder saw them
    for (std::uint32_t node : holder_nodes_) {
      const std::size_t n = g_->nodes[node].terms.size();
      for (std::size_t k = 0; k < n * (n - 1) / 2; ++k) {
        const std::uint32_t id = enumerated_[next++];
        if (initial_[id].holders < 2) continue;
        if (record_of_[id] == kNone) record_of_[id] = new_record(id);
        Holders& holders = pairs_[record_of_[id]].holders;
        if (holders.empty() || holders.back().node != node) {
          holders.push_back({node, 1});
        } else {
          ++holders.back().times;
        }
      }
    }
    enumerated_ = {};
    std::vector<Ranked> entries;
    for (std::uint32_t p = 0; p < pairs_.size(); ++p) entries.push_back(ranked(p, false));
    if (watching_) by_key_ = std::priority_queue<Ranked>(std::less<Ranked>(), entries);
    if (ties_ == PairTies::ExistingFirst) {
      for (Ranked& r : entries) r.exact = exact(r.pair);
    }
    ranked_ = std::priority_queue<Ranked>(std::less<Ranked>(), std::move(entries));
  }

  // Extracts the pair with the most holders (the smallest key among equals).
  // Returns false when no pair has two holders.
  bool extract_best() {
    const std::uint32_t best = pop_best(ranked_, ties_ == PairTies::ExistingFirst);
    if (watching_ && pop_best(by_key_, false) != best) fork();
    if (best == kNone) return false;
    const std::uint64_t key = pairs_[best].key;
    const std::uint32_t pair =
        g_->append(Node::of(op_of(key), {{lo_of(key), false}, {hi_of(key), differ_of(key)}}));
    detail::SmallVector<std::uint32_t, 16> holder_list;  // increasing node order
    for (const Holder& h : pairs_[best].holders) holder_list.push_back(h.node);
    for (std::uint32_t node : holder_list) {
      std::size_t i = 0;
      std::size_t j = 0;
      while (find(node, key, &i, &j)) {
        const bool sign = g_->nodes[node].terms[i].neg;
        remove_term(node, std::max(i, j));
        remove_term(node, std::min(i, j));
        add_term(node, {pair, sign});
      }
    }
    for (std::uint32_t p : risen_) {
      pairs_[p].risen = false;
      if (holders(p) < 2) continue;
      ranked_.push(ranked(p, ties_ == PairTies::ExistingFirst));
      if (watching_) by_key_.push(ranked(p, false));
    }
    risen_.clear();
    return true;
  }

  // The graph as ties by key make it, where they would have chosen another
  // pair at some step; nothing where they agree with this run throughout.
  std::optional<Graph> finish_by_key();

 private:
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};

  struct Holder {
    std::uint32_t node;
    int times;  // > 0
  };
  // Inline up to four: most tracked pairs have a few holders, and there are
  // thousands of pairs.
  using Holders = detail::SmallVector<Holder, 4>;

  // A tracked pair.
  struct Pair {
    std::uint64_t key;
    bool risen = false;  // in risen_
    Holders holders;     // by increasing node
  };

  // The initial count of a pair: its distinct holders, and the last one counted.
  struct InitialCount {
    std::uint32_t last_holder = kNone;
    int holders = 0;
  };

  // A heap entry: the pair had `holders` holders, `exact` of them the pair
  // itself, when pushed.
  struct Ranked {
    int holders;
    int exact;
    std::uint64_t key;
    std::uint32_t pair;
    // Most holders first, then most exact holders, then the smallest key.
    friend bool operator<(const Ranked& a, const Ranked& b) {
      if (a.holders != b.holders) return a.holders < b.holders;
      if (a.exact != b.exact) return a.exact < b.exact;
      return a.key > b.key;
    }
  };

  template <class F>
  void for_each_pair(std::uint32_t node, F&& f) const {
    const Terms& terms = g_->nodes[node].terms;
    const Op op = g_->nodes[node].op;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      for (std::size_t j = i + 1; j < terms.size(); ++j) f(key_of(op, terms[i], terms[j]));
    }
  }

  // The dense id of a pair key, given on first sight.
  std::uint32_t id_of(std::uint64_t key) {
    auto [id, inserted] = index_.try_emplace(key, static_cast<std::uint32_t>(keys_.size()));
    if (inserted) {
      keys_.push_back(key);
      initial_.emplace_back();
      record_of_.push_back(kNone);
    }
    return *id;
  }

  std::uint32_t new_record(std::uint32_t id) {
    pairs_.push_back({keys_[id], false, {}});
    return static_cast<std::uint32_t>(pairs_.size() - 1);
  }

  int holders(std::uint32_t p) const { return static_cast<int>(pairs_[p].holders.size()); }

  // Holders of two operands, which are the pair itself. Why they rank a pair
  // higher: extracting a pair saves one operation per holder but the first
  // either way, but a longer holder gives up its other pairs for it, and
  // the pair itself has none (c3·c5 beside c3·s4·c5: extracting c3·c5 leaves
  // s4 free to pair elsewhere, extracting c3·s4 would not).
  // A constant's pair counts too (0.5·y beside 0.5·x·y): where the pair
  // alone takes its readers' sign, (-0.5)·y, and shares nothing,
  // compile_program keeps the other order.
  int exact(std::uint32_t p) const {
    int n = 0;
    for (const Holder& h : pairs_[p].holders) n += g_->nodes[h.node].terms.size() == 2 ? 1 : 0;
    return n;
  }

  // with_exact: ranked by ExistingFirst, else by key.
  Ranked ranked(std::uint32_t p, bool with_exact) const {
    return {holders(p), with_exact ? exact(p) : 0, pairs_[p].key, p};
  }

  std::uint32_t pop_best(std::priority_queue<Ranked>& heap, bool with_exact) {
    while (!heap.empty()) {
      const Ranked top = heap.top();
      const Ranked now = ranked(top.pair, with_exact);
      if (now.holders == top.holders && now.exact == top.exact) return top.pair;
      heap.pop();  // stale: the counts have changed since
      if (now.holders >= 2) heap.push(now);
    }
    return kNone;
  }

  // Copies the graph and the table as they are, to go on by key from here:
  // the heap by key is the one a run by key would have now.
  void fork();

  // Positions i != j of the pair's operands in node (with matching signs).
  bool find(std::uint32_t node, std::uint64_t key, std::size_t* i, std::size_t* j) const {
    const Terms& terms = g_->nodes[node].terms;
    const std::uint32_t lo = lo_of(key);
    const std::uint32_t hi = hi_of(key);
    for (std::size_t a = 0; a < terms.size(); ++a) {
      if (terms[a].id != lo) continue;
      for (std::size_t b = 0; b < terms.size(); ++b) {
        if (b == a || terms[b].id != hi) continue;
        if (op_of(key) == Op::Sum && (terms[a].neg != terms[b].neg) != differ_of(key)) continue;
        *i = a;
        *j = b;
        return true;
      }
    }
    return false;
  }

  void remove_term(std::uint32_t node, std::size_t position) {
    Terms& terms = g_->nodes[node].terms;
    for (std::size_t q = 0; q < terms.size(); ++q) {
      if (q != position) count(key_of(g_->nodes[node].op, terms[position], terms[q]), node, -1);
    }
    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(position));
  }

  void add_term(std::uint32_t node, Term t) {
    Terms& terms = g_->nodes[node].terms;
    for (Term other : terms) count(key_of(g_->nodes[node].op, t, other), node, +1);
    terms.push_back(t);
  }

  // Adds delta (+1 or -1) to the number of times node holds the pair, after rank().
  void count(std::uint64_t key, std::uint32_t node, int delta) {
    const std::uint32_t* found = index_.find(key);
    if (found == nullptr && delta < 0) return;  // never counted: not a pair of a holder
    const std::uint32_t id = found != nullptr ? *found : id_of(key);
    if (record_of_[id] == kNone) {
      if (found == nullptr) {
        record_of_[id] = new_record(id);  // a pair with a fresh operand
      } else if (delta > 0) {
        throw std::logic_error(fmt::format("pair CSE: untracked pair {:#x} gains a holder", key));
      } else {
        return;  // one holder at most, for ever
      }
    }
    const std::uint32_t p = record_of_[id];
    Pair& pair = pairs_[p];
    auto it = std::lower_bound(pair.holders.begin(), pair.holders.end(), node,
                               [](const Holder& h, std::uint32_t n) { return h.node < n; });
    if (it != pair.holders.end() && it->node == node) {
      if ((it->times += delta) == 0) pair.holders.erase(it);
      return;
    }
    if (delta < 0)
      throw std::logic_error(fmt::format("pair CSE: node {} loses a pair it does not hold", node));
    pair.holders.insert(it, {node, delta});
    if (!pair.risen) {
      pair.risen = true;
      risen_.push_back(p);
    }
  }

  struct Fork;

  Graph* g_;
  PairTies ties_;
  bool watching_;                            // by_key_ is kept, no fork yet
  detail::FlatMap64<std::uint32_t> index_;   // key -> dense id
  std::vector<std::uint64_t> keys_;          // (by id)
  std::vector<std::uint32_t> record_of_;     // (by id) index in pairs_, kNone if untracked
  std::vector<Pair> pairs_;                  // the tracked pairs
  std::vector<InitialCount> initial_;        // (by id) the counts rank() starts from
  std::vector<std::uint32_t> enumerated_;    // until rank(): ids of each holder's pairs, in order
  std::vector<std::uint32_t> holder_nodes_;  // every holder, increasing
  std::priority_queue<Ranked> ranked_;       // tracked pairs, holders >= 2 when pushed
  std::priority_queue<Ranked> by_key_;       // while watching_: the same entries ranked by key
  std::shared_ptr<Fork> forked_;             // the run by key from where it parts
  std::vector<std::uint32_t> risen_;         // pairs whose count rose in this extraction
};

// The copies a run by key goes on with (fork()).
struct PairTable::Fork {
  Fork(const Graph& g, const PairTable& t) : graph(g), table(t) { table.g_ = &graph; }
  Graph graph;
  PairTable table;
};

void PairTable::fork() {
  forked_ = std::make_shared<Fork>(*g_, *this);
  PairTable& t = forked_->table;
  t.ties_ = PairTies::ByKey;
  t.ranked_ = std::move(t.by_key_);
  t.by_key_ = {};
  t.watching_ = false;
  watching_ = false;
  by_key_ = {};
}

std::optional<Graph> PairTable::finish_by_key() {
  if (!forked_) return std::nullopt;
  while (forked_->table.extract_best()) {
  }
  return std::move(forked_->graph);
}

// The pairs of the graph's live sums and products, counted and ranked by
// ExistingFirst, watching what ties by key would choose.
PairTable ranked_pairs(Graph& graph) {
  if (graph.nodes.size() > kMaxPairOperandId) {
    throw UsageError(fmt::format("pair CSE: {} program nodes, more than the pair keys can hold",
                                 graph.nodes.size()));
  }
  const std::vector<char> live = graph.live();
  std::vector<std::uint32_t> holders;
  std::size_t pairs = 0;
  for (std::uint32_t id = 0; id < live.size(); ++id) {
    const Node& node = graph.nodes[id];
    const bool nary = node.op == Op::Sum || node.op == Op::Prod;
    if (!live[id] || !nary || node.terms.size() > kMaxPairOperands) continue;
    holders.push_back(id);
    pairs += node.terms.size() * (node.terms.size() - 1) / 2;
  }
  // Sized to the program: a small one's table is cleared in no time.
  PairTable table(graph, PairTies::ExistingFirst, pairs, true);
  for (std::uint32_t id : holders) table.add_holder(id);
  table.rank();
  return table;
}

}  // namespace

std::optional<Graph> extract_common_pairs(Graph& graph) {
  PairTable table = ranked_pairs(graph);
  while (table.extract_best()) {
  }
  return table.finish_by_key();
}

}  // namespace symdyn::symbolic::ir
