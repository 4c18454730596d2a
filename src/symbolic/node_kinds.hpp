#pragma once
// The table of expression node kinds, written once. Every pass that needs a
// per-kind fact (its name, arity, C++ spelling, cost) reads it from here, so
// adding a kind is adding a row.
//
//   X(Kind, "name", arity, "C++ spelling", cost)
//
// arity: 0 for leaves, -1 for n-ary, else the fixed number of arguments.
// cost: weight of one evaluation in the operation count (an add or a multiply
//       costs 1; calls cost more, roughly their latency relative to a multiply).

#define SYMDYN_FOR_EACH_LEAF_KIND(X) \
  X(Rational, "rational", 0, "", 0)  \
  X(Real, "real", 0, "", 0)          \
  X(Symbol, "symbol", 0, "", 0)

#define SYMDYN_FOR_EACH_ALGEBRAIC_KIND(X) \
  X(Add, "add", -1, "+", 1)               \
  X(Mul, "mul", -1, "*", 1)               \
  X(Pow, "pow", 2, "std::pow", 4)

#define SYMDYN_FOR_EACH_FUNCTION_KIND(X) \
  X(Sin, "sin", 1, "std::sin", 10)       \
  X(Cos, "cos", 1, "std::cos", 10)       \
  X(Tan, "tan", 1, "std::tan", 12)       \
  X(Asin, "asin", 1, "std::asin", 12)    \
  X(Acos, "acos", 1, "std::acos", 12)    \
  X(Atan, "atan", 1, "std::atan", 12)    \
  X(Atan2, "atan2", 2, "std::atan2", 14) \
  X(Exp, "exp", 1, "std::exp", 10)       \
  X(Log, "log", 1, "std::log", 10)       \
  X(Abs, "abs", 1, "std::abs", 1)

#define SYMDYN_FOR_EACH_KIND(X)     \
  SYMDYN_FOR_EACH_LEAF_KIND(X)      \
  SYMDYN_FOR_EACH_ALGEBRAIC_KIND(X) \
  SYMDYN_FOR_EACH_FUNCTION_KIND(X)
