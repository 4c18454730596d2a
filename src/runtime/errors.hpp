#pragma once
// The exceptions of the runtime. Messages name the culprit: the body, the
// coordinate, the entry point, the time and state at which a number went bad.

#include <stdexcept>
#include <string>

namespace symdyn::runtime {

// Base of every error the runtime reports.
class RuntimeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A model that cannot be simulated as described: a non-physical inertia, an
// unknown body or coordinate name, a missing entry point, mismatched sizes.
class ModelError : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

// A computation that went wrong numerically: a value that is not finite, a
// singular or indefinite mass matrix, a solver that did not converge.
class NumericError : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

}  // namespace symdyn::runtime
