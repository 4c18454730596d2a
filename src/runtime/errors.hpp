#pragma once
// The exceptions of the runtime. Messages name the culprit: the time, the
// quantity and the coordinate or extra state ("t = 0.5: qdd of coordinate
// 'x' is nan"), the option, or the body.

#include <stdexcept>
#include <string>

namespace symdyn::runtime {

// Base of every error the runtime reports.
class RuntimeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A model that cannot be simulated as given: bad sizes, bad inertia, an
// unknown name.
class ModelError : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

// A computation that went numerically wrong: a value not finite, a step size
// below the minimum, a Newton iteration that does not converge, a singular
// matrix.
class NumericError : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

// A setting the caller got wrong: an unknown integrator name, a negative
// tolerance, a fixed-step run without a step.
class OptionError : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

}  // namespace symdyn::runtime
