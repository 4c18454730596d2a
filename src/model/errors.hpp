#pragma once

#include <stdexcept>

namespace symdyn::model {

// A model that cannot be right: the message names the body, symbol or
// parameter at fault ("body 'arm2': inertia not positive definite").
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace symdyn::model
