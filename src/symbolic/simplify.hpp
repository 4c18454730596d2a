#pragma once
// Opt-in simplification: expand, and simplify by keeping the cheapest of
// several equivalent forms.
//
// Construction already applies the cheap canonical rules (expr.hpp). This adds
// what a construction rule cannot decide locally: whether a sum of products of
// sines and cosines is cheaper contracted (cos q0 cos q1 - sin q0 sin q1 =
// cos(q0 + q1)), with the Pythagorean identity applied, expanded, or as it is.
//
// simplify builds candidate forms of every sum, product and power, bottom-up:
//   - the node as it is, and rebuilt from its simplified operands;
//   - the contracting rules (trig_rules.hpp) applied where they lower the cost;
//   - expand, then contract;
//   - for trigonometric nodes: sin² -> 1 - cos² (or cos² -> 1 - sin²), expand,
//     contract (a normal form modulo sin² + cos² = 1, then the short form);
//     products linearized to sums of sin/cos of sums of angles (Giac's tlin),
//     contract; sin/cos of sums expanded, expand, contract;
// and keeps the one with the lowest operation_cost (cost.hpp), the input on a
// tie. A node that still holds asin, acos or atan2 once rebuilt is only
// contracted: the arguments of those functions are algebraic, not angles, and
// on every reference model expanding such nodes cost generation time and never
// found a cheaper form (bench/results/emitted_code_layout.md). It repeats on its
// result until nothing is cheaper. Hence:
//   - operation_cost(simplify(e)) <= operation_cost(e), always;
//   - simplify(simplify(e)) == simplify(e);
//   - simplify(e) equals e wherever e is defined (every rule is an identity,
//     and construction never shrinks a domain).
// Work is bounded: expansion stops distributing beyond a number of terms, and
// rewriting has a per-node budget (rewrite.hpp).

#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/node_table.hpp>
#include <symdyn/symbolic/rewrite.hpp>

namespace symdyn::symbolic {

// Distributes products over sums and expands positive integer powers of sums,
// everywhere (inside function arguments too). A product or power whose
// expansion would have more than max_terms terms is left factored.
// Memoized by node id: a shared subexpression is expanded once.
class Expander {
 public:
  explicit Expander(std::size_t max_terms = 512) : max_terms_(max_terms) {}
  Expr operator()(Expr e);

 private:
  Expr expand_product(std::span<const Expr> factors);
  Expr expand_power(Expr base, const Number& exponent);
  std::size_t max_terms_;
  detail::ExprMemo memo_;
};

Expr expand(Expr e);

// A simplifier that remembers what it has done: simplifying many expressions
// that share subexpressions (the entries of a kinematic chain) costs each node
// once. It belongs to the context current at its construction.
class Simplifier {
 public:
  Simplifier();

  // The cheapest form found; see the guarantees above.
  Expr operator()(Expr e);

  // Simplifies several outputs deciding on their joint cost (shared nodes
  // counted once): each output is simplified, then kept as it was where that
  // lowers the total. The total never exceeds that of the inputs.
  std::vector<Expr> operator()(std::span<const Expr> outputs);

 private:
  Expr once(Expr e);
  Expr best_form(Expr original, Expr rebuilt);
  Expr linearize(Expr e);
  static constexpr std::uint8_t kTrig = 1;         // sin, cos
  static constexpr std::uint8_t kInverseTrig = 2;  // asin, acos, atan2
  std::uint8_t functions_held(Expr e);
  std::size_t expanded_terms(Expr e);

  Expander expand_;
  Rewriter contract_;
  Rewriter eliminate_sin_;
  Rewriter eliminate_cos_;
  Rewriter linearize_;
  Rewriter expand_trig_;
  detail::ExprMemo memo_;
  std::unordered_map<std::uint32_t, std::uint8_t> functions_memo_;
  std::unordered_map<std::uint32_t, std::size_t> terms_memo_;
};

Expr simplify(Expr e);
std::vector<Expr> simplify(std::span<const Expr> outputs);

}  // namespace symdyn::symbolic
