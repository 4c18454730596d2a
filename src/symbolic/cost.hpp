#pragma once
// The operation count of expressions: what simplify minimizes.
//
// operation_cost(outputs) estimates the floating-point work of evaluating all
// the outputs once, as the emitted straight-line code would: every node of the
// DAG reachable from the outputs is computed once (shared nodes count once),
// and a node costs
//
//   number, symbol            0
//   sum of k terms            k - 1 additions; a term with a negative
//                             coefficient is a subtraction, so -x costs nothing
//   product of k factors      k - 1 multiplications, not counting a numeric
//                             coefficient; a coefficient other than +1 or -1
//                             costs one more multiply (and -1 is free: it
//                             folds into the enclosing subtraction); a factor
//                             y^-n is a division by y^n, which replaces the
//                             multiplication (x/y costs 1)
//   x^n, n integer            the multiplications of binary powering
//                             (x^2: 1, x^3: 2, x^4: 2), plus one division if n < 0
//   x^r, r not an integer     the `cost` column of Pow in node_kinds.hpp
//   f(x)                      the `cost` column of f in node_kinds.hpp
//
// It is a model, not a measurement: a call weighs roughly its latency in
// multiplies, and an output that is a bare negation is counted as free.

#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

// Total cost of evaluating every output, nodes shared between outputs counted once.
int operation_cost(std::span<const Expr> outputs);
int operation_cost(Expr e);

// As operation_cost, with sin(x) and cos(x) of one x counted as one call, as
// the emitted code computes them (a sincos).
int fused_operation_cost(std::span<const Expr> outputs);

// The cost of the node e alone, and the nodes it needs computed: its
// operands, except that a reciprocal factor y^-n of a product needs y.
int own_cost(Expr e, std::vector<Expr>* operands);

// Multiplications needed for x^n by binary powering, n >= 1.
int power_multiplications(std::int64_t n);

}  // namespace symdyn::symbolic
