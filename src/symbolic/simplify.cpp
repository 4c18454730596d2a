// expand and simplify; see simplify.hpp.
#include <algorithm>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/detail/trig_rules.hpp>
#include <symdyn/symbolic/simplify.hpp>

namespace symdyn::symbolic {
namespace {

std::span<const Expr> terms_of(const Expr& e) {
  return e.kind() == Kind::Add ? e.args() : std::span<const Expr>(&e, 1);
}

// The cheapest of the candidates, `original` on a tie.
Expr cheapest(Expr original, std::initializer_list<Expr> candidates) {
  Expr best = original;
  int best_cost = operation_cost(original);
  for (Expr c : candidates) {
    if (c == best) continue;
    const int cost = operation_cost(c);
    if (cost < best_cost) {
      best = c;
      best_cost = cost;
    }
  }
  return best;
}

// Limits on the candidate forms worth contracting (see best_form).
constexpr std::size_t kMaxContractTerms = 96;
constexpr int kMaxGrowth = 3;
constexpr int kGrowthSlack = 40;
// Nodes whose expansion would have more terms than this only get contracted
// as they are: expanding them grows with the product of their factors' terms
// (a chain of n rotations expands into 3^n), the expanded form would be too
// big to contract anyway, and their operands were already simplified.
constexpr std::size_t kMaxExpandedTerms = 4 * kMaxContractTerms;
// Only nodes up to this cost are expanded: beyond, the search is long and
// rarely shorter. Products to sums and sin and cos of sums, which multiply
// terms further (a product of k sines is 2^(k-1) terms), only up to half of it.
constexpr int kMaxExpandCost = 256;

std::vector<Rule> concat(std::vector<Rule> a, std::vector<Rule> b) {
  a.insert(a.end(), std::make_move_iterator(b.begin()), std::make_move_iterator(b.end()));
  return a;
}

}  // namespace

// ---- expand ----

Expr Expander::operator()(Expr e) {
  if (e.args().empty()) return e;
  if (const Node* done = memo_.find(e)) return Expr(done);
  std::vector<Expr> args;
  args.reserve(e.args().size());
  for (Expr a : e.args()) args.push_back((*this)(a));
  Expr out;
  switch (e.kind()) {
    case Kind::Mul:
      out = expand_product(args);
      break;
    case Kind::Pow:
      out = expand_power(args[0], args[1].number());
      break;
    default:
      out = make(e.kind(), args);
      break;
  }
  memo_.set(e, out);
  return out;
}

// (a + b)(c + d) = ac + ad + bc + bd, factor by factor.
Expr Expander::expand_product(std::span<const Expr> factors) {
  std::size_t count = 1;
  for (Expr f : factors) count *= terms_of(f).size();
  if (count > max_terms_) return mul(factors);
  std::vector<Expr> terms{Expr(1)};
  for (Expr f : factors) {
    std::vector<Expr> next;
    next.reserve(terms.size() * terms_of(f).size());
    for (Expr t : terms) {
      for (Expr u : terms_of(f)) next.push_back(t * u);
    }
    terms = std::move(next);
  }
  return add(terms);
}

// (a + b)^n for an integer n >= 2 as a product of n sums, expanded.
Expr Expander::expand_power(Expr base, const Number& exponent) {
  if (base.kind() != Kind::Add || !exponent.is_integer() || exponent.num() < 2)
    return pow(base, Expr(exponent));
  const std::int64_t n = exponent.num();
  if (n > 16) return pow(base, Expr(exponent));
  const std::vector<Expr> factors(static_cast<std::size_t>(n), base);
  return expand_product(factors);
}

Expr expand(Expr e) {
  return Expander()(e);
}

// ---- simplify ----

Simplifier::Simplifier()
    : contract_(concat(contracting_trig_rules(), algebraic_rules()), Strategy::Improve),
      eliminate_sin_(sin_squared_elimination(), Strategy::Normalize),
      eliminate_cos_(cos_squared_elimination(), Strategy::Normalize),
      linearize_(linearizing_trig_rules(), Strategy::Normalize),
      expand_trig_(expanding_trig_rules(), Strategy::Normalize) {}

Expr Simplifier::operator()(Expr e) {
  // Repeat until the form is stable: each round is strictly cheaper or the
  // same node, so this ends, and the result is a fixpoint (idempotence).
  Expr current = e;
  for (int round = 0; round < 64; ++round) {
    const Expr next = once(current);
    if (next == current) break;
    current = next;
  }
  return current;
}

std::vector<Expr> Simplifier::operator()(std::span<const Expr> outputs) {
  std::vector<Expr> out;
  out.reserve(outputs.size());
  for (Expr e : outputs) out.push_back((*this)(e));
  int best = operation_cost(out);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out[i] == outputs[i]) continue;
    std::vector<Expr> trial = out;
    trial[i] = outputs[i];
    const int cost = operation_cost(trial);
    if (cost < best) {
      out = std::move(trial);
      best = cost;
    }
  }
  if (operation_cost(outputs) <= best) return {outputs.begin(), outputs.end()};
  return out;
}

// One bottom-up pass: operands first, then the cheapest candidate at the node.
Expr Simplifier::once(Expr e) {
  if (e.args().empty()) return e;
  if (const Node* done = memo_.find(e)) return Expr(done);
  std::vector<Expr> args;
  args.reserve(e.args().size());
  bool changed = false;
  for (Expr a : e.args()) {
    args.push_back(once(a));
    changed = changed || args.back() != a;
  }
  const Expr rebuilt = changed ? make(e.kind(), args) : e;
  const bool algebraic = e.kind() == Kind::Add || e.kind() == Kind::Mul || e.kind() == Kind::Pow;
  const Expr out = algebraic ? best_form(e, rebuilt) : cheapest(e, {rebuilt, contract_(rebuilt)});
  memo_.set(e, out);
  return out;
}

Expr Simplifier::best_form(Expr original, Expr rebuilt) {
  Expr best = original;
  int best_cost = operation_cost(original);
  auto consider = [&](Expr candidate) {
    if (candidate == best) return;
    const int cost = operation_cost(candidate);
    if (cost < best_cost) {
      best = candidate;
      best_cost = cost;
    }
  };
  const int rebuilt_cost = operation_cost(rebuilt);
  // A form much bigger than the node is not worth contracting: the search
  // would be long and the result rarely shorter.
  auto contract_if_small = [&](Expr form) {
    if (terms_of(form).size() > kMaxContractTerms ||
        operation_cost(form) > kMaxGrowth * rebuilt_cost + kGrowthSlack)
      return;
    consider(contract_(form));
  };
  consider(rebuilt);
  consider(contract_(rebuilt));
  if (functions_held(rebuilt) & kInverseTrig) return best;
  if (rebuilt_cost > kMaxExpandCost || expanded_terms(rebuilt) > kMaxExpandedTerms) return best;
  contract_if_small(expand_(rebuilt));
  if (!(functions_held(rebuilt) & kTrig)) return best;
  contract_if_small(expand_(eliminate_sin_(rebuilt)));
  contract_if_small(expand_(eliminate_cos_(rebuilt)));
  if (rebuilt_cost > kMaxExpandCost / 2) return best;
  contract_if_small(linearize(rebuilt));
  contract_if_small(expand_(expand_trig_(rebuilt)));
  return best;
}

// tlin: linearize products of sines and cosines, expand, until stable.
Expr Simplifier::linearize(Expr e) {
  Expr current = expand_(e);
  for (int round = 0; round < 8; ++round) {
    const Expr next = expand_(linearize_(current));
    if (next == current) break;
    current = next;
  }
  return current;
}

// The number of terms of the full expansion before like terms are collected,
// saturated just above kMaxExpandedTerms.
std::size_t Simplifier::expanded_terms(Expr e) {
  if (e.args().empty()) return 1;
  if (auto it = terms_memo_.find(e.id()); it != terms_memo_.end()) return it->second;
  constexpr std::size_t saturated = kMaxExpandedTerms + 1;
  std::size_t n = 1;
  switch (e.kind()) {
    case Kind::Add:
      n = 0;
      for (Expr a : e.args()) n = std::min(saturated, n + expanded_terms(a));
      break;
    case Kind::Mul:
      for (Expr a : e.args()) n = std::min(saturated, n * expanded_terms(a));
      break;
    case Kind::Pow:
      if (!e.args()[1].is_number()) break;
      if (const Number& k = e.args()[1].number(); k.is_integer() && k.num() >= 2) {
        for (std::int64_t i = 0; i < k.num() && n < saturated; ++i)
          n = std::min(saturated, n * expanded_terms(e.args()[0]));
      }
      break;
    default:
      break;  // a function call is one term
  }
  terms_memo_.emplace(e.id(), n);
  return n;
}

// Which of the function families the gates of best_form look for a node
// holds, memoized: one walk answers both.
std::uint8_t Simplifier::functions_held(Expr e) {
  std::uint8_t held = 0;
  if (e.kind() == Kind::Sin || e.kind() == Kind::Cos) held = kTrig;
  if (e.kind() == Kind::Asin || e.kind() == Kind::Acos || e.kind() == Kind::Atan2)
    held = kInverseTrig;
  if (e.args().empty()) return held;
  if (auto it = functions_memo_.find(e.id()); it != functions_memo_.end()) return it->second;
  for (Expr a : e.args()) held |= functions_held(a);
  functions_memo_.emplace(e.id(), held);
  return held;
}

Expr simplify(Expr e) {
  return Simplifier()(e);
}

std::vector<Expr> simplify(std::span<const Expr> outputs) {
  return Simplifier()(outputs);
}

}  // namespace symdyn::symbolic
