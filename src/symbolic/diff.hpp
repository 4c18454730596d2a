#pragma once
// Differentiation, total time derivative, directional derivative and substitution.
//
// All are memoized sweeps over the DAG (see dag_map.hpp): each node is
// processed once per sweep object, so the result of differentiating a DAG of n
// nodes has O(n) new nodes (times the arity of products), however much the
// DAG shares. Keep one Differentiator / TimeDerivative / Substitution object
// alive to process many expressions that share nodes; the free functions make
// a fresh one per call.
//
// Derivatives are built from one table of local partials (partial() below) by
// the chain rule
//     d f(a_0, ..., a_k) = sum_i  ∂f/∂a_i · d a_i,
// skipping the arguments whose derivative is an exact zero, so constant
// subexpressions cost nothing. Products use the n-ary product rule
//     d (f_0 · ... · f_k) = sum_i (prod_{j != i} f_j) · d f_i,
// never e·sum(f_i'/f_i), which would divide by factors that may vanish.
//
// The partials are the real-domain closed forms, with no case split:
//   sin: cos(x)              asin: 1/sqrt(1 - x²)      exp: exp(x)
//   cos: -sin(x)             acos: -1/sqrt(1 - x²)     log: 1/x
//   tan: 1 + tan(x)²         atan: 1/(1 + x²)          abs: x/|x| (the sign)
//   x^e: e·x^(e-1)           atan2(y, x): (x, -y)/(x² + y²)
// They hold wherever the function is differentiable; at the points where it is
// not (|x| at 0, sqrt at 0, asin at ±1) the derivative evaluates to a
// division by zero, as the math says. No rule introduces complex numbers.
//
// The results are canonical (built through the smart constructors of expr.hpp)
// but not simplified: simplification is a separate pass.

#include <span>
#include <unordered_map>

#include <symdyn/symbolic/dag_map.hpp>
#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

// ∂node/∂(node.arg(i)), the local partial derivative of a compound node with
// respect to its i-th argument, in terms of the node and its arguments.
// Throws UsageError for a leaf, for i out of range, and for the exponent of a
// power (a constant by the grammar, so its partial is never needed).
Expr partial(Expr node, std::size_t i);

// d e / d variable. Throws UsageError if `variable` is not a symbol.
class Differentiator {
 public:
  explicit Differentiator(Expr variable);
  Expr operator()(Expr e);

 private:
  DagMap map_;
};
Expr diff(Expr e, Expr variable);

// The time derivative of each symbol that varies with time: q -> qd, qd -> qdd,
// p -> pd, ... Keys must be symbols.
using RateMap = std::unordered_map<Expr, Expr>;

// The total time derivative d e / dt, in one sweep. A symbol's derivative is
// its entry in the rate map; a symbol absent from the map has derivative 1 if
// its kind is Time, 0 if Parameter or Free (constants); any other kind
// (Variable, Rate, Acceleration, Dependent, ...) throws UsageError naming the
// symbol and its kind: "time derivative: symbol 'q0' (variable) has no rate
// given". The rate expressions themselves are not differentiated: a second
// derivative is a second sweep, with a map that gives the rates of the rates.
// The constructor throws UsageError if a key of `rates` is not a symbol.
class TimeDerivative {
 public:
  explicit TimeDerivative(RateMap rates);
  Expr operator()(Expr e);

 private:
  DagMap map_;
};
Expr time_derivative(Expr e, const RateMap& rates);

// The derivative along a direction: each symbol's derivative is its entry in
// `tangents` (absent: 0, whatever its kind), so that d e = Σ_a ∂e/∂a · tangent(a)
// in one sweep, a Jacobian-vector product.
class DirectionalDerivative {
 public:
  explicit DirectionalDerivative(std::unordered_map<Expr, Expr> tangents);
  DirectionalDerivative(const DirectionalDerivative&) = delete;
  DirectionalDerivative& operator=(const DirectionalDerivative&) = delete;
  Expr operator()(Expr e);
  // The tangent of a symbol no earlier call has met (its image is fixed once
  // met): lets a chain of definitions be differentiated in order. Throws
  // UsageError otherwise.
  void add(Expr symbol, Expr tangent);

 private:
  std::unordered_map<Expr, Expr> tangents_;
  DagMap map_;
};

// e with every symbol of `replacements` replaced by its value, rebuilt
// through the smart constructors (so the result is canonical: x·y with x -> 2
// gives 2y, and folded constants may raise DomainError or DivisionByZero, as
// log(x) with x -> 0 does). Nodes that contain no replaced symbol are kept as
// they are. Replacement is simultaneous (x -> y, y -> x swaps) and not
// repeated on the values. The constructor throws UsageError if a key is not a
// symbol.
class Substitution {
 public:
  explicit Substitution(std::unordered_map<Expr, Expr> replacements);
  Substitution(const Substitution&) = delete;
  Substitution& operator=(const Substitution&) = delete;
  Expr operator()(Expr e);
  // One more replacement, for a symbol no earlier call has met (its image is
  // fixed once met): lets a chain of definitions be substituted in order.
  // Throws UsageError otherwise.
  void add(Expr symbol, Expr value);

 private:
  std::unordered_map<Expr, Expr> replacements_;
  DagMap map_;
};
Expr substitute(Expr e, const std::unordered_map<Expr, Expr>& replacements);

}  // namespace symdyn::symbolic
