#pragma once
// The symbols behind each input array of the emitted functions (t, q, qd,
// qdd, tau, param), and the C++ text of their elements.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/model/model.hpp>

namespace symdyn::codegen::detail {

class InputSymbols {
 public:
  // Makes the symbols of tau (model::generalized_force_symbols).
  explicit InputSymbols(const model::Model& model);

  const std::vector<model::Expr>& operator[](Input input) const { return symbols_[index(input)]; }
  std::size_t size(Input input) const { return (*this)[input].size(); }

  // The symbols of these inputs, in order: a program's inputs.
  std::vector<model::Expr> of(const std::vector<Input>& inputs) const;
  // Every input's, in the order of kInputs: the shared program's inputs.
  std::vector<model::Expr> all() const;
  // The indices of these inputs' symbols among all().
  std::vector<std::size_t> indices(const std::vector<Input>& inputs) const;

 private:
  static std::size_t index(Input input) { return static_cast<std::size_t>(input); }
  std::array<std::vector<model::Expr>, std::size(kInputs)> symbols_;
};

// The C++ text of element i of an input array ("q[3]"); the time t is a scalar.
std::string input_element(Input input, std::size_t i);

// "name[i]", without a format string: an entry point names thousands of elements.
std::string element(std::string_view name, std::size_t i);

}  // namespace symdyn::codegen::detail
