// DAG -> IR (see program_ir.hpp), and the sharing of reciprocals.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <queue>

#include <symdyn/symbolic/detail/flat_map.hpp>
#include <symdyn/symbolic/detail/program_ir.hpp>
#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/scalar_ops.hpp>

namespace symdyn::symbolic::ir {

std::size_t Graph::hash(const Node& node) {
  std::size_t h = (static_cast<std::size_t>(node.op) << 8) ^ static_cast<std::size_t>(node.kind);
  for (Term t : node.terms) h = mix_hash(h, (std::uint64_t{t.id} << 1) | std::uint64_t{t.neg});
  h = mix_hash(h, std::bit_cast<std::uint64_t>(node.constant));
  return finish_hash(mix_hash(h, node.input));
}

bool Graph::same(const Node& a, const Node& b) {
  return a.op == b.op && a.kind == b.kind && a.input == b.input &&
         std::bit_cast<std::uint64_t>(a.constant) == std::bit_cast<std::uint64_t>(b.constant) &&
         a.terms == b.terms;
}

std::uint32_t Graph::intern(Node node) {
  if (node.op == Op::Sum || node.op == Op::Prod) std::sort(node.terms.begin(), node.terms.end());
  const std::size_t h = hash(node);
  if (2 * (indexed_ + 1) > slots_.size()) grow_index();
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = h & mask;
  for (; slots_[i] != 0; i = (i + 1) & mask) {
    const std::uint32_t id = slots_[i] - 1;
    if (hashes_[id] == h && same(nodes[id], node)) return id;
  }
  const auto id = static_cast<std::uint32_t>(nodes.size());
  slots_[i] = id + 1;
  ++indexed_;
  hashes_.push_back(h);
  nodes.push_back(std::move(node));
  return id;
}

void Graph::grow_index() {
  const std::vector<std::uint32_t> old = std::move(slots_);
  slots_.assign(std::max<std::size_t>(1024, 2 * old.size()), 0);
  const std::size_t mask = slots_.size() - 1;
  for (std::uint32_t slot : old) {
    if (slot == 0) continue;
    std::size_t i = hashes_[slot - 1] & mask;
    while (slots_[i] != 0) i = (i + 1) & mask;
    slots_[i] = slot;
  }
}

std::uint32_t Graph::append(Node node) {
  hashes_.push_back(0);
  nodes.push_back(std::move(node));
  return static_cast<std::uint32_t>(nodes.size() - 1);
}

std::uint32_t Graph::constant(double value) {
  Node node = Node::of(Op::Const);
  node.constant = value;
  return intern(std::move(node));
}

std::uint32_t Graph::materialize(Term value) {
  if (!value.neg) return value.id;
  if (nodes[value.id].op == Op::Const) return constant(-nodes[value.id].constant);
  return intern(Node::of(Op::Neg, {{value.id, false}}));
}

std::vector<char> Graph::live() const {
  std::vector<char> seen(nodes.size(), 0);
  std::vector<std::uint32_t> stack;
  for (Term t : outputs) stack.push_back(t.id);
  while (!stack.empty()) {
    const std::uint32_t id = stack.back();
    stack.pop_back();
    if (seen[id]) continue;
    seen[id] = true;
    for (Term t : nodes[id].terms) stack.push_back(t.id);
  }
  return seen;
}

namespace {

// Exponents computed by multiplications (and one sqrt for halves), as in
// scalar::power: integers and halves of integers up to kMaxMultipliedPower.
bool is_multiplied_power(const Number& e) {
  if (!e.is_exact()) return false;
  const std::int64_t limit = scalar::kMaxMultipliedPower;
  if (e.den() == 1) return e.num() >= -limit && e.num() <= limit;
  return e.den() == 2 && e.num() >= -2 * limit && e.num() <= 2 * limit;
}

// What the symbols of a program are: inputs (by symbol node id, their index)
// or definitions (by symbol node id, their value). Open-addressing tables:
// every entry point indexes the model's thousand definitions again.
class Symbols {
 public:
  Symbols(std::span<const Definition> definitions, std::size_t inputs)
      : definitions_(definitions), input_of_(inputs), definition_of_(definitions.size()) {}

  // Whether the symbol is new.
  bool add_input(std::uint32_t id, std::uint32_t index) {
    return input_of_.try_emplace(id, index).second;
  }
  bool add_definition(std::uint32_t id, std::uint32_t index) {
    return definition_of_.try_emplace(id, index).second;
  }

  const std::uint32_t* input(std::uint32_t id) const { return input_of_.find(id); }
  bool is_input(std::uint32_t id) const { return input_of_.find(id) != nullptr; }
  bool is_defined(std::uint32_t id) const { return definition_of_.find(id) != nullptr; }
  // The value of a defined symbol, or nullptr.
  const Expr* definition(std::uint32_t id) const {
    const std::uint32_t* i = definition_of_.find(id);
    return i == nullptr ? nullptr : &definitions_[*i].value;
  }

 private:
  std::span<const Definition> definitions_;
  detail::FlatMap64<std::uint32_t> input_of_;
  detail::FlatMap64<std::uint32_t> definition_of_;  // index in definitions_
};

// A value by node id, for one pass at a time: each pass stamps what it sets,
// so the table is kept (by thread) and never cleared, and a small program in
// a large context neither clears a table of every node nor hashes its own.
class IdTable {
 public:
  // The table of `slot` (0 or 1), its values all unset.
  static IdTable& fresh(int slot) {
    thread_local std::array<IdTable, 2> tables;
    IdTable& t = tables[static_cast<std::size_t>(slot)];
    if (++t.stamp_ == 0) {  // the stamps wrapped around: old entries could collide
      std::fill(t.entries_.begin(), t.entries_.end(), Entry{});
      t.stamp_ = 1;
    }
    return t;
  }

  const std::uint32_t* find(std::uint32_t id) const {
    return id < entries_.size() && entries_[id].stamp == stamp_ ? &entries_[id].value : nullptr;
  }
  // Sets id's value if unset; whether it was.
  bool try_set(std::uint32_t id, std::uint32_t value) {
    if (id >= entries_.size()) entries_.resize(std::max<std::size_t>(id + 1, 2 * entries_.size()));
    Entry& e = entries_[id];
    if (e.stamp == stamp_) return false;
    e = {stamp_, value};
    return true;
  }

 private:
  struct Entry {
    std::uint32_t stamp = 0;
    std::uint32_t value = 0;
  };
  std::vector<Entry> entries_;
  std::uint32_t stamp_ = 0;
};

class Lowerer {
 public:
  Lowerer(Graph& graph, const Symbols& symbols)
      : g_(graph), symbols_(symbols), memo_(IdTable::fresh(0)) {}

  // Lowers e, whose arguments are already lowered.
  void lower(Expr e) {
    const Term t = lower_node(e);
    memo_.try_set(e.id(), (t.id << 1) | std::uint32_t{t.neg});
  }
  // Lowered before: see lower().
  Term lowered(Expr e) const {
    const std::uint32_t t = *memo_.find(e.id());
    return {t >> 1, (t & 1U) != 0};
  }

 private:
  Term lower_node(Expr e) {
    switch (e.kind()) {
      case Kind::Rational:
      case Kind::Real: {
        const double v = e.number().to_double();
        return v < 0 ? Term{g_.constant(-v), true} : Term{g_.constant(v), false};
      }
      case Kind::Symbol: {
        if (const Expr* value = symbols_.definition(e.id())) {
          return lowered(*value);  // the value of its definition, lowered before it
        }
        Node node = Node::of(Op::Input);
        node.input = *symbols_.input(e.id());
        return {g_.intern(std::move(node)), false};
      }
      case Kind::Add:
        return lower_sum(e);
      case Kind::Mul:
        return lower_product(e);
      case Kind::Pow:
        return lower_power(lowered(e.arg(0)), e.arg(1).number());
      default: {
        Node node = Node::of(Op::Call);
        node.kind = e.kind();
        for (Expr a : e.args()) node.terms.push_back({g_.materialize(lowered(a)), false});
        return {g_.intern(std::move(node)), false};
      }
    }
  }

  // A sum is stored with at least one positive term: -a - b is -(a + b).
  Term lower_sum(Expr e) {
    Terms terms;
    terms.reserve(e.args().size());
    for (Expr t : e.args()) terms.push_back(lowered(t));
    return make_sum(std::move(terms));
  }

  Term make_sum(Terms terms) {
    if (terms.size() == 1) return terms[0];
    const bool all_negative = std::all_of(terms.begin(), terms.end(), [](Term t) { return t.neg; });
    if (all_negative) {
      for (Term& t : terms) t.neg = false;
    }
    return {g_.intern(Node::of(Op::Sum, std::move(terms))), all_negative};
  }

  // c·x·y⁻¹·z⁻² = ±(|c|·x)/(y·z²): one division by the product of the denominators.
  Term lower_product(Expr e) {
    bool neg = false;
    detail::SmallVector<std::uint32_t, 8> numerator;
    detail::SmallVector<std::uint32_t, 8> denominator;
    for (Expr f : e.args()) {
      if (f.is_number()) {
        const double c = f.number().to_double();
        neg = neg != (c < 0);
        if (std::abs(c) != 1.0) numerator.push_back(g_.constant(std::abs(c)));
        continue;
      }
      const bool divides = f.kind() == Kind::Pow && f.arg(1).number().is_negative() &&
                           is_multiplied_power(f.arg(1).number());
      const Term t = divides ? lower_power(lowered(f.arg(0)), -f.arg(1).number()) : lowered(f);
      neg = neg != t.neg;
      (divides ? denominator : numerator).push_back(t.id);
    }
    if (denominator.empty()) return {product(numerator), neg};
    const std::uint32_t top = numerator.empty() ? g_.constant(1.0) : product(numerator);
    return {divide(top, product(denominator)), neg};
  }

  std::uint32_t product(std::span<const std::uint32_t> factors) {
    if (factors.size() == 1) return factors[0];
    Node node = Node::of(Op::Prod);
    node.terms.reserve(factors.size());
    for (std::uint32_t f : factors) node.terms.push_back({f, false});
    return g_.intern(std::move(node));
  }

  std::uint32_t divide(std::uint32_t numerator, std::uint32_t denominator) {
    return g_.intern(Node::of(Op::Div, {{numerator, false}, {denominator, false}}));
  }

  Term lower_power(Term base, const Number& e) {
    if (!is_multiplied_power(e)) {
      Node node = Node::of(Op::Pow, {{g_.materialize(base), false}});
      node.constant = e.to_double();
      return {g_.intern(std::move(node)), false};
    }
    if (e.is_negative()) {
      const Term positive = lower_power(base, -e);
      return {divide(g_.constant(1.0), positive.id), positive.neg};
    }
    if (e.is_integer()) return {integer_power(base.id, e.num()), base.neg && e.num() % 2 != 0};
    // x^(k/2) = x^((k-1)/2)·sqrt(x)
    const std::uint32_t x = g_.materialize(base);
    const std::uint32_t root = g_.intern(Node::of(Op::Sqrt, {{x, false}}));
    const std::int64_t whole = (e.num() - 1) / 2;
    if (whole == 0) return {root, false};
    const std::uint32_t factors[] = {integer_power(x, whole), root};
    return {product(factors), false};
  }

  // Repeated squaring, as scalar::integer_power: x^(2m) = (x^m)^2, x^(2m+1) = x^(2m)·x.
  std::uint32_t integer_power(std::uint32_t x, std::int64_t n) {
    if (n == 1) return x;
    if (n % 2 == 0) {
      const std::uint32_t half = integer_power(x, n / 2);
      const std::uint32_t factors[] = {half, half};
      return product(factors);
    }
    const std::uint32_t factors[] = {integer_power(x, n - 1), x};
    return product(factors);
  }

  Graph& g_;
  const Symbols& symbols_;
  IdTable& memo_;  // by node id: the term's id << 1 | neg
};

// Throws UsageError for a non-symbol, a repeated input or a symbol both input and defined.
Symbols index_symbols(std::span<const Expr> inputs, std::span<const Definition> definitions) {
  Symbols symbols(definitions, inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (!inputs[i].is_symbol()) {
      throw UsageError(
          fmt::format("compile_program: input {} ({}) is not a symbol", i, inputs[i].str()));
    }
    if (!symbols.add_input(inputs[i].id(), static_cast<std::uint32_t>(i))) {
      throw UsageError(fmt::format(
          "compile_program: symbol '{}' is given twice as an input (positions {} and {})",
          inputs[i].name(), *symbols.input(inputs[i].id()), i));
    }
  }
  for (std::size_t i = 0; i < definitions.size(); ++i) {
    const Definition& d = definitions[i];
    if (!d.symbol.is_symbol()) {
      throw UsageError(fmt::format(
          "compile_program: a definition names '{}', which is not a symbol", d.symbol.str()));
    }
    if (symbols.is_input(d.symbol.id())) {
      throw UsageError(fmt::format("compile_program: symbol '{}' is both an input and defined",
                                   d.symbol.name()));
    }
    if (!symbols.add_definition(d.symbol.id(), static_cast<std::uint32_t>(i))) {
      throw UsageError(
          fmt::format("compile_program: symbol '{}' is defined twice", d.symbol.name()));
    }
  }
  return symbols;
}

// Calls f on what node e needs computed before it: its arguments, or a
// defined symbol's value.
template <class F>
void for_each_dependency(Expr e, const Symbols& symbols, F&& f) {
  if (const Expr* value = symbols.definition(e.id())) {
    f(*value);
    return;
  }
  for (Expr a : e.args()) f(a);
}

// Nodes left waiting after Kahn's algorithm each wait for another: walking
// from one to a waiting dependency, nodes.size() steps surely end on a cycle,
// and every cycle passes through a definition (the DAG itself has none).
[[noreturn]] void throw_cycle(const std::vector<Expr>& nodes,
                              const std::vector<std::size_t>& waiting, const IdTable& index,
                              const Symbols& symbols) {
  std::size_t at = 0;
  while (waiting[at] == 0) ++at;
  auto step = [&](std::size_t i) {
    std::size_t next = i;
    bool found = false;
    for_each_dependency(nodes[i], symbols, [&](Expr d) {
      if (!found && waiting[*index.find(d.id())] > 0) {
        next = *index.find(d.id());
        found = true;
      }
    });
    return next;
  };
  for (std::size_t k = 0; k < nodes.size(); ++k) at = step(at);
  while (!symbols.is_defined(nodes[at].id())) at = step(at);
  throw UsageError(
      fmt::format("compile_program: the definition of '{}' depends on itself", nodes[at].name()));
}

// Kahn's algorithm over `nodes` (closed under dependencies), the smallest
// node id first among the ready ones. Without definitions this is id order.
std::vector<Expr> topological_order(std::vector<Expr> nodes, const Symbols& symbols) {
  IdTable& index = IdTable::fresh(1);  // node id -> position in nodes
  for (std::size_t i = 0; i < nodes.size(); ++i)
    index.try_set(nodes[i].id(), static_cast<std::uint32_t>(i));
  std::vector<std::size_t> waiting(nodes.size(), 0);  // dependencies not yet ordered
  // The positions of every node's dependencies, node after node.
  std::vector<std::uint32_t> dependency;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for_each_dependency(nodes[i], symbols, [&](Expr d) {
      dependency.push_back(static_cast<std::uint32_t>(*index.find(d.id())));
      ++waiting[i];
    });
  }
  // The users of node i are users[first_user[i] .. first_user[i + 1]).
  std::vector<std::size_t> first_user(nodes.size() + 1, 0);
  for (std::uint32_t d : dependency) ++first_user[d + 1];
  for (std::size_t i = 0; i < nodes.size(); ++i) first_user[i + 1] += first_user[i];
  std::vector<std::uint32_t> users(dependency.size());
  std::vector<std::size_t> filled(first_user.begin(), first_user.end() - 1);
  for (std::size_t i = 0, k = 0; i < nodes.size(); ++i) {
    for (const std::size_t end = k + waiting[i]; k < end; ++k)
      users[filled[dependency[k]]++] = static_cast<std::uint32_t>(i);
  }
  // Ready nodes as (node id, position): the smallest key is the smallest id.
  auto key = [&](std::size_t i) { return (std::uint64_t{nodes[i].id()} << 32) | i; };
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<>> ready;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (waiting[i] == 0) ready.push(key(i));
  }
  std::vector<Expr> order;
  order.reserve(nodes.size());
  while (!ready.empty()) {
    const auto i = static_cast<std::size_t>(ready.top() & 0xffffffffU);
    ready.pop();
    order.push_back(nodes[i]);
    for (std::size_t k = first_user[i]; k < first_user[i + 1]; ++k) {
      if (--waiting[users[k]] == 0) ready.push(key(users[k]));
    }
  }
  if (order.size() < nodes.size()) throw_cycle(nodes, waiting, index, symbols);
  return order;
}

// Every node the outputs need, each after what it depends on, ties broken by
// node id (so the order does not depend on the order of the outputs).
std::vector<Expr> reachable(std::span<const Expr> outputs, const Symbols& symbols) {
  std::vector<Expr> found;
  IdTable& seen = IdTable::fresh(0);
  std::vector<Expr> stack;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    stack.push_back(outputs[i]);
    while (!stack.empty()) {
      const Expr e = stack.back();
      stack.pop_back();
      if (!seen.try_set(e.id(), 0)) continue;
      if (e.is_symbol() && !symbols.is_input(e.id()) && !symbols.is_defined(e.id())) {
        throw UsageError(fmt::format(
            "compile_program: output {} uses symbol '{}', which is neither an input nor defined", i,
            e.name()));
      }
      found.push_back(e);
      for_each_dependency(e, symbols, [&](Expr d) { stack.push_back(d); });
    }
  }
  return topological_order(std::move(found), symbols);
}
}  // namespace

Graph lower(std::span<const Expr> inputs, std::span<const Expr> outputs,
            std::span<const Definition> definitions) {
  const Symbols symbols = index_symbols(inputs, definitions);
  Graph graph;
  const std::vector<Expr> order = reachable(outputs, symbols);
  graph.nodes.reserve(order.size() + order.size() / 4);
  Lowerer lowerer(graph, symbols);
  for (Expr e : order) lowerer.lower(e);
  for (Expr e : outputs) graph.outputs.push_back(lowerer.lowered(e));
  return graph;
}

// When k divisions share a denominator d, 1/d once and k multiplications cost
// less than k divisions (a division weighs 4 multiplies) from k = 2 on, or
// from k = 1 when 1/d is computed anyway.
void fold_reciprocals(Graph& graph) {
  const std::vector<char> live = graph.live();
  std::map<std::uint32_t, std::vector<std::uint32_t>> divisions;  // denominator -> divisions, by id
  for (std::uint32_t id = 0; id < graph.nodes.size(); ++id) {
    if (live[id] && graph.nodes[id].op == Op::Div)
      divisions[graph.nodes[id].terms[1].id].push_back(id);
  }
  auto is_one = [&](std::uint32_t id) {
    return graph.nodes[id].op == Op::Const && graph.nodes[id].constant == 1.0;
  };
  for (const auto& [denominator, users] : divisions) {
    std::vector<std::uint32_t> others;
    for (std::uint32_t d : users) {
      if (!is_one(graph.nodes[d].terms[0].id)) others.push_back(d);
    }
    const bool has_reciprocal = others.size() < users.size();
    if (others.size() < (has_reciprocal ? 1U : 2U)) continue;
    const std::uint32_t one = graph.constant(1.0);
    const std::uint32_t reciprocal =
        graph.intern(Node::of(Op::Div, {{one, false}, {denominator, false}}));
    for (std::uint32_t d : others) {
      Terms terms{graph.nodes[d].terms[0], {reciprocal, false}};
      std::sort(terms.begin(), terms.end());
      graph.nodes[d] = Node::of(Op::Prod, std::move(terms));
    }
  }
}

}  // namespace symdyn::symbolic::ir
