#pragma once
// Jacobians of expressions written through a chain of definitions, by forward
// mode over the definitions (what a compiler would do to the straight-line
// program they make):
//
//   d s/d x_j = Σ_a ∂value(s)/∂a · d a/d x_j    for every definition s = value(s),
//
// a running over the variables and the earlier defined symbols that value(s)
// reads. A defined symbol's derivative is itself a definition
// ("d(s)/d(x_j)"), so that a quantity used by many later ones is
// differentiated once and its derivative read where needed, and the result is
// as long as the program times the number of directions at most: forward mode
// over a recursive algorithm stays linear in its length per direction.
// Derivatives that are numbers or symbols replace their symbol as they are,
// so a zero cancels every term it multiplies and the definitions a variable
// does not reach cost nothing.
//
// The variables are symbols; every other symbol that is not defined is a
// constant (derivative 0).

#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

struct ChainJacobian {
  std::vector<Expr> entries;  // (outputs x variables), row-major
  std::vector<Definition>
      definitions;  // the defined symbols' derivatives, each after those it uses
};

// d outputs_i / d variables_j through `definitions` (each after those it
// uses, as compile_program takes them). Only the definitions the outputs
// reach are differentiated. Throws UsageError if a variable is not a symbol
// or is defined.
ChainJacobian chain_jacobian(std::span<const Expr> outputs, std::span<const Expr> variables,
                             std::span<const Definition> definitions);

}  // namespace symdyn::symbolic
