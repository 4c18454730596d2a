#pragma once
// Direct numeric evaluation of expressions on the DAG: each node once,
// memoized by node id. The straight-line Program (program.hpp) is the fast path;
// this is the simple reference it is tested against.

#include <fmt/format.h>

#include <unordered_map>
#include <vector>

#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/scalar_ops.hpp>

namespace symdyn::symbolic {

// Values of symbols, keyed by the symbol.
template <class S>
using Bindings = std::unordered_map<Expr, S>;

template <class S>
class Evaluator {
 public:
  explicit Evaluator(const Bindings<S>& bindings) : bindings_(bindings) {}

  // Throws UsageError naming a symbol without a value.
  S operator()(Expr e) {
    if (auto it = memo_.find(e.id()); it != memo_.end()) return it->second;
    S value = compute(e);
    memo_.emplace(e.id(), value);
    return value;
  }

 private:
  S compute(Expr e) {
    switch (e.kind()) {
      case Kind::Rational:
      case Kind::Real:
        return S(e.number().to_double());
      case Kind::Symbol: {
        auto it = bindings_.find(e);
        if (it == bindings_.end())
          throw UsageError(fmt::format("evaluate: symbol '{}' has no value", e.name()));
        return it->second;
      }
      case Kind::Add: {
        S sum = S(0);
        for (Expr a : e.args()) sum = sum + (*this)(a);
        return sum;
      }
      case Kind::Mul: {
        S product = S(1);
        for (Expr a : e.args()) product = product * (*this)(a);
        return product;
      }
      case Kind::Pow:
        return scalar::power((*this)(e.arg(0)), e.arg(1).number());
      default: {
        std::vector<S> args;
        for (Expr a : e.args()) args.push_back((*this)(a));
        return scalar::call<S>(e.kind(), args);
      }
    }
  }

  const Bindings<S>& bindings_;
  std::unordered_map<std::uint32_t, S> memo_;
};

template <class S>
S evaluate(Expr e, const Bindings<S>& bindings) {
  return Evaluator<S>(bindings)(e);
}

}  // namespace symdyn::symbolic
