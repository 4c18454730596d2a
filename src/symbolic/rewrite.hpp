#pragma once
// Rewrite rules as data, and the one engine that applies them.
//
// A rule is a row {name, pattern, replacement, condition}. Patterns and
// replacements are ordinary expressions in which some symbols are wildcards,
// so a rule reads like the math:
//
//   rule("sin2+cos2", _a*pow(sin(_x), 2) + _a*pow(cos(_x), 2), _a)
//
// Wildcards are symbols of SymbolKind::Free whose name starts with '_'
// (reserved for patterns). What a wildcard matches depends on its name:
//
//   _a _b _c _d   cofactor: as a factor of a product pattern, the rest of the
//                 product, numeric coefficient included (it may be 1 or a bare
//                 number); anywhere else, any expression
//   _R _S ...     rest (an upper-case letter): as a term of a sum pattern, the
//                 remaining terms (may be 0); as a factor, like a cofactor
//   _x _y ...     any other name: one expression; as a product factor, one
//                 whole factor (power included)
//
// Matching is modulo commutativity and sub-multisets:
//   - a sum pattern matches distinct terms of a target sum in any order; at the
//     top of a rule the unmatched terms are kept (the replacement is added to
//     them); nested in a pattern, they must be captured by a rest wildcard or
//     there must be none;
//   - a product pattern c·f1·...·fk·_a matches any expression seen as a product
//     (coefficient times factors; a lone x is 1·x, a number is a coefficient):
//     the fi match distinct factors, an integer power counting as that many
//     factors (sin(_x)^2 matches inside sin(q)^3, leaving sin(q)); the cofactor
//     _a binds to (target coefficient / c) times the leftover factors, and
//     without a cofactor the leftover must be exactly 1;
//   - other nodes match node for node; a power's exponent must be equal.
// A wildcard that occurs twice must bind to the same (interned) expression.
//
// Conditions are sound: they return true only when the property is known to
// hold for every value of the symbols (unknown means no).
//
// The Rewriter applies a rule set bottom-up, memoized by node id, to a
// fixpoint under a per-node budget, with one of two strategies:
//   Improve    a rewrite is accepted only if it strictly lowers the
//              operation_cost of the node (after its new parts are rewritten
//              too), so it never makes anything costlier and always stops;
//   Normalize  every match is applied (for rule sets that terminate by
//              themselves, such as sin^2 -> 1 - cos^2).
// With SYMDYN_TRACE_RULES=1 in the environment each rule that fires prints its
// name on stderr.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/node_table.hpp>

namespace symdyn::symbolic {

// A wildcard: the Free symbol `name`, which must start with '_'.
Expr wildcard(std::string_view name);
bool is_wildcard(Expr e);

// The bindings of one match.
class Match {
 public:
  // The expression bound to a wildcard; throws UsageError if it is unbound.
  Expr operator[](Expr wildcard) const;
  Expr operator[](std::string_view wildcard_name) const;
  std::optional<Expr> find(Expr wildcard) const;

  void bind(Expr wildcard, Expr value) { bindings_.emplace_back(wildcard, value); }
  void unbind() { bindings_.pop_back(); }
  const std::vector<std::pair<Expr, Expr>>& bindings() const { return bindings_; }

  // Terms of the target sum a top-level sum pattern matched, and those it
  // left unmatched.
  std::vector<Expr> matched;
  std::vector<Expr> remainder;

 private:
  std::vector<std::pair<Expr, Expr>> bindings_;
};

using Condition = std::function<bool(const Match&)>;

struct Rule {
  std::string name;
  Expr pattern;
  Expr replacement;
  Condition condition;  // empty: always
};

// A checked rule row. Throws UsageError naming the rule if the pattern is a
// bare wildcard, if the replacement uses a wildcard the pattern does not bind,
// or if a product (sum) pattern has two cofactors (rests).
Rule rule(std::string name, Expr pattern, Expr replacement, Condition condition = {});

// Sound conditions on a wildcard's binding.
Condition nonnegative(std::string_view wildcard_name);  // known >= 0 for all values
// Not a sum, and its numeric coefficient is an integer (2q, -3xy, q; not q/2).
Condition integer_coefficient(std::string_view wildcard_name);
bool is_nonnegative(Expr e);  // true only if e >= 0 wherever it is defined

// Every match of `pattern` at the root of `target` (at most `limit`), for
// tests and tools. A top-level sum pattern fills Match::remainder.
std::vector<Match> find_matches(Expr pattern, Expr target, std::size_t limit = 256);

// The replacement with its wildcards replaced by their bindings, rebuilt
// through the smart constructors, plus the match's remainder terms.
Expr instantiate(Expr replacement, const Match& match);

enum class Strategy { Improve, Normalize };

// Limits that keep rewriting bounded on any input. They are per node, so the
// result for a node never depends on what was rewritten before it.
struct Budget {
  int steps_per_node = 64;        // rule applications at one node
  int attempts_per_rule = 20000;  // match steps of one rule at one node
};

class MatchCache;

class Rewriter {
 public:
  Rewriter(std::vector<Rule> rules, Strategy strategy, Budget budget = {});
  ~Rewriter();
  Rewriter(Rewriter&&) noexcept;

  // e rewritten bottom-up to a fixpoint (or until the budget runs out).
  Expr operator()(Expr e);

  const std::vector<Rule>& rules() const { return rules_; }

 private:
  Expr rewrite(Expr e);
  Expr rewrite_children(Expr e);
  Expr apply_at(Expr e);
  std::optional<Expr> step(Expr e, int cost);
  std::optional<Expr> improve_sum(Expr e, int cost);

  std::vector<Rule> rules_;
  Strategy strategy_;
  Budget budget_;
  detail::ExprMemo memo_;
  detail::NodeTable<std::uint8_t> in_progress_;  // 1 while being rewritten
  std::unique_ptr<MatchCache> cache_;
};

}  // namespace symdyn::symbolic
