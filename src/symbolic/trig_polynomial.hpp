#pragma once
// A polynomial normal form in sines and cosines modulo sin²x + cos²x = 1.
//
// Why: a sum such as m·(c3·s4·c5 + s3·s5)² + m·(c3·s4·s5 - s3·c5)² + m·c3²·c4²
// is the constant m, but no local rewrite sees it: the squares must be
// expanded and the terms collected across the whole sum first. The rule
// engine (rewrite.hpp) matches a few terms at a time; this pass works on the
// whole polynomial instead.
//
// An expression is read as a polynomial over atoms: every node that is not a
// sum, a product, a positive integer power or a number is an atom (sin x and
// cos x among them; a symbol with a definition is seen through, its value
// read in its place, unless that value's polynomial is too big). In each
// monomial sin²x is replaced by 1 - cos²x until no sine appears squared:
// two polynomials equal modulo sin²x + cos²x = 1 for every x then have the
// same terms. Products whose expansion would exceed `max_terms` terms are
// kept as atoms (so the form is always found, perhaps less reduced).
//
// Inexact coefficients: terms whose coefficients cancel to within rounding
// (|sum| <= 32 ε · the largest coefficient added into it) are dropped, as
// the exact identity they come from says (186·c² - 186.00000000000003·c²
// is 0 to rounding, and meant to be 0). Exact coefficients cancel exactly.

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

class TrigPolynomialForm {
 public:
  // `definitions`: symbols standing for expressions, each after those it
  // uses (they are seen through, see above).
  explicit TrigPolynomialForm(std::span<const Definition> definitions = {},
                              std::size_t max_terms = 32);
  ~TrigPolynomialForm();
  TrigPolynomialForm(const TrigPolynomialForm&) = delete;
  TrigPolynomialForm& operator=(const TrigPolynomialForm&) = delete;

  // The normal form of e, expanded, as an expression equal to e (to rounding
  // of inexact coefficients).
  Expr operator()(Expr e);

  // The number of terms of e's normal form.
  std::size_t terms(Expr e);
  // A lower bound of the operation count of e's normal form (operation_cost),
  // the cost of its atoms aside.
  int cost_lower_bound(Expr e);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Each output, and each definition's value, replaced by its normal form
// (with definitions seen through) where that is cheaper than the expression
// as written, the definitions and calls it uses counted as free (a call it
// adds is the sin of a cos it has, or the cos of a sin: one sincos in the
// emitted code). Each value is weighed alone, not the sharing between them:
// a reduced value can share less with the others than it did (a few
// operations, rarely), which the programs compiled from them show (the
// generator compares those). Outputs and definitions that do not hold sin
// or cos are kept as they are.
struct PythagoreanReduction {
  std::vector<Expr> outputs;
  std::vector<Definition> definitions;
};
PythagoreanReduction reduce_pythagorean(std::span<const Expr> outputs,
                                        std::span<const Definition> definitions,
                                        std::span<const Definition> context_definitions = {});

}  // namespace symdyn::symbolic
