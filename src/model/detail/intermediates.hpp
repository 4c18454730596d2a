#pragma once
// Named intermediates: a derived quantity that many others use is replaced by
// a symbol of kind Intermediate, defined once, so that the expressions using
// it stay short and the program computes it once (symbolic/program.hpp).
//
// Only sums are named: a number, a symbol or a number times one is as cheap to
// repeat as to read, and a product is what the canonical form keeps shared
// anyway; a sum is what it would flatten into the sums that use it.

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::model {

class IntermediateNames {
 public:
  // The value itself, or coefficient·symbol for the sum it holds; a sum met
  // before keeps its first name. Throws std::logic_error if the name was
  // given to another sum (a bug of the caller).
  symbolic::Expr operator()(symbolic::Expr value, const std::string& name);

  // Names every entry of an array of expressions "<prefix><index>".
  template <class Array>
  void name_all(Array& entries, const std::string& prefix) {
    for (std::size_t i = 0; i < entries.size(); ++i)
      entries[i] = (*this)(entries[i], prefix + std::to_string(i));
  }

  // The definitions made so far, each after those it uses.
  const std::vector<symbolic::Definition>& definitions() const { return definitions_; }
  std::vector<symbolic::Definition> take_definitions() { return std::move(definitions_); }

 private:
  std::vector<symbolic::Definition> definitions_;
  std::unordered_map<symbolic::Expr, symbolic::Expr> names_;  // value -> its symbol
  std::unordered_set<std::string> used_names_;
};

}  // namespace symdyn::model
