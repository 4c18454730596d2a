#pragma once
// The exceptions of the symbolic engine. Messages name the culprit.

#include <stdexcept>
#include <string>

namespace symdyn::symbolic {

// Base of every error the engine reports.
class SymbolicError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Division by an exact zero, or an exact zero raised to a negative power.
class DivisionByZero : public SymbolicError {
 public:
  using SymbolicError::SymbolicError;
};

// A constant outside a function's domain (asin(2), log(0), sqrt(-1)).
class DomainError : public SymbolicError {
 public:
  using SymbolicError::SymbolicError;
};

// An engine function used the wrong way (differentiating with respect to a
// non-symbol, a symbol of the wrong kind, an unknown input, ...).
class UsageError : public SymbolicError {
 public:
  using SymbolicError::SymbolicError;
};

}  // namespace symdyn::symbolic
