#pragma once
// Numeric constants of the engine: an exact rational (64-bit numerator and
// denominator, always reduced, denominator > 0) or a double. Arithmetic stays
// exact while the result fits in 64 bits and becomes a double otherwise, so
// constant folding never overflows silently.
//
// Doubles that are exactly a small dyadic rational (2.0, 0.5, -0.25) are stored
// as rationals: no information is lost, and 2.0*x and 2*x are the same node.

#include <compare>
#include <cstdint>
#include <limits>
#include <string>

namespace symdyn::symbolic {

// Exact intermediate products of two 64-bit values.
__extension__ typedef __int128 WideInt;  // NOLINT(modernize-use-using): __extension__ needs typedef

class Number {
 public:
  Number() = default;
  // An integer: inline, as constructions make one per operand. The one
  // integer whose negation does not fit becomes a double, like any overflow.
  Number(std::int64_t num) : num_(num) {  // NOLINT(google-explicit-constructor)
    if (num == std::numeric_limits<std::int64_t>::min()) *this = Number(num, 1);
  }
  Number(std::int64_t num, std::int64_t den);  // throws DivisionByZero if den == 0
  static Number from_double(double value);

  bool is_exact() const { return exact_; }
  bool is_integer() const { return exact_ && den_ == 1; }
  std::int64_t num() const { return num_; }  // exact only
  std::int64_t den() const { return den_; }  // exact only
  double to_double() const;

  bool is_zero() const { return exact_ ? num_ == 0 : value_ == 0.0; }
  bool is_one() const { return exact_ ? num_ == 1 && den_ == 1 : value_ == 1.0; }
  bool is_negative() const { return exact_ ? num_ < 0 : value_ < 0.0; }

  friend Number operator+(const Number& a, const Number& b);
  friend Number operator-(const Number& a, const Number& b);
  friend Number operator*(const Number& a, const Number& b);
  friend Number operator/(const Number& a, const Number& b);  // throws DivisionByZero on exact 0
  Number operator-() const;
  // a^n for an integer n; exact when a is exact and the result fits.
  friend Number pow_integer(const Number& a, std::int64_t n);

  // Total order: by value, then exact before inexact (so 1/2 and 0.5 never tie).
  friend std::strong_ordering compare(const Number& a, const Number& b);
  friend bool operator==(const Number& a, const Number& b) { return compare(a, b) == 0; }

  std::string str() const;  // "3", "-1/2", or a round-trip double "9.81"

 private:
  static Number make_exact(WideInt num, WideInt den);
  bool exact_ = true;
  std::int64_t num_ = 0;
  std::int64_t den_ = 1;
  double value_ = 0.0;
};

}  // namespace symdyn::symbolic
