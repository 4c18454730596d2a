#pragma once
// A seeded generator of random expressions for property tests.
//
// The expressions stay inside their real domains at any point whose
// coordinates lie in [-2, 2]: arguments of asin/acos are squashed into
// (-1, 1) by sin(u)/2, log and sqrt get u^2 + 1/2, division gets u^2 + 1, and
// atan2 gets a positive second argument. Every kind of node appears.

#include <random>
#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::testing {

class RandomExpr {
 public:
  RandomExpr(unsigned seed, std::vector<symbolic::Expr> symbols)
      : rng_(seed), symbols_(std::move(symbols)) {}

  symbolic::Expr operator()(int depth) {
    using namespace symbolic;
    if (depth <= 0 || pick(5) == 0) return leaf();
    const Expr a = (*this)(depth - 1);
    switch (pick(17)) {
      case 0:
      case 1:
        return a + (*this)(depth - 1);
      case 2:
        return a - (*this)(depth - 1);
      case 3:
      case 4:
        return a * (*this)(depth - 1);
      case 5:
        return a / (pow(leaf(), 2) + 1);
      case 6:
        return pow(a, static_cast<int>(pick(4)) + 2);
      case 7:
        return sqrt(pow(a, 2) + rational(1, 2));
      case 8:
        return sin(a);
      case 9:
        return cos(a);
      case 10:
        return tan(sin(a) / 2);
      case 11:
        return asin(sin(a) / 2);
      case 12:
        return acos(cos(a) / 2);
      case 13:
        return atan(a);
      case 14:
        return atan2(a, pow(leaf(), 2) + 1);
      case 15:
        return exp(sin(a)) + log(pow(a, 2) + rational(1, 2));
      default:
        return abs(a) + rational(1, 3) * a;
    }
  }

  symbolic::Expr leaf() {
    using namespace symbolic;
    if (pick(4) == 0) {
      // Two statements: the order of evaluation of arguments is unspecified, and
      // a seed must give the same expression under every compiler.
      const auto num = static_cast<std::int64_t>(pick(7)) - 3;
      const auto den = static_cast<std::int64_t>(pick(3)) + 1;
      return rational(num, den);
    }
    return symbols_[pick(symbols_.size())];
  }

  // A point with every symbol in [-2, 2].
  std::vector<double> point() {
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    std::vector<double> p(symbols_.size());
    for (double& v : p) v = u(rng_);
    return p;
  }

  std::size_t pick(std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }
  std::mt19937& rng() { return rng_; }

 private:
  std::mt19937 rng_;
  std::vector<symbolic::Expr> symbols_;
};

}  // namespace symdyn::testing
