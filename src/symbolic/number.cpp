#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numeric>

#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/number.hpp>

namespace symdyn::symbolic {
namespace {

constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();

bool fits(WideInt v) {
  return v <= kInt64Max && v >= -kInt64Max;
}

WideInt gcd128(WideInt a, WideInt b) {
  if (a < 0) a = -a;
  if (b < 0) b = -b;
  while (b != 0) {
    const WideInt t = a % b;
    a = b;
    b = t;
  }
  return a;
}

std::int64_t gcd64(WideInt a, WideInt b) {
  return static_cast<std::int64_t>(std::gcd(static_cast<std::uint64_t>(a < 0 ? -a : a),
                                            static_cast<std::uint64_t>(b < 0 ? -b : b)));
}

Number inexact(double v) {
  Number n = Number::from_double(v);
  return n;
}

}  // namespace

Number::Number(std::int64_t num, std::int64_t den) {
  if (den == 0) throw DivisionByZero(fmt::format("rational {}/0: division by an exact zero", num));
  *this = make_exact(num, den);
}

Number Number::make_exact(WideInt num, WideInt den) {
  if (den < 0) {
    num = -num;
    den = -den;
  }
  // Most constants are small integers: skip the division loop, and run it in
  // 64 bits when both parts fit (128-bit remainders are a library call).
  WideInt g = 1;
  if (den != 1) g = fits(num) && fits(den) ? WideInt{gcd64(num, den)} : gcd128(num, den);
  if (g > 1) {
    num /= g;
    den /= g;
  }
  Number n;
  if (fits(num) && fits(den)) {
    n.num_ = static_cast<std::int64_t>(num);
    n.den_ = static_cast<std::int64_t>(den);
  } else {
    n.exact_ = false;
    n.value_ = static_cast<double>(num) / static_cast<double>(den);
  }
  return n;
}

Number Number::from_double(double value) {
  // A double is a dyadic rational m·2^e; keep it exact when it is a small one.
  if (std::isfinite(value)) {
    int e = 0;
    const double m = std::frexp(value, &e);   // value = m·2^e, 0.5 <= |m| < 1
    const double scaled = std::ldexp(m, 53);  // exact integer
    constexpr int kMaxDenominatorBits = 20;
    // value = scaled · 2^(e - 53); strip trailing zero bits of scaled.
    auto integer = static_cast<std::int64_t>(scaled);
    int shift = e - 53;
    while (integer != 0 && integer % 2 == 0 && shift < 0) {
      integer /= 2;
      ++shift;
    }
    if (integer == 0) return Number(0);
    if (shift >= 0 && shift < 10) return Number(integer * (std::int64_t{1} << shift));
    if (shift < 0 && -shift <= kMaxDenominatorBits)
      return Number(integer, std::int64_t{1} << -shift);
  }
  Number n;
  n.exact_ = false;
  n.value_ = value;
  return n;
}

double Number::to_double() const {
  return exact_ ? static_cast<double>(num_) / static_cast<double>(den_) : value_;
}

Number operator+(const Number& a, const Number& b) {
  // Integers (exponents, most coefficients): no 128-bit arithmetic, same result.
  if (std::int64_t sum = 0;
      a.is_integer() && b.is_integer() && !__builtin_add_overflow(a.num_, b.num_, &sum)) {
    return Number::make_exact(sum, 1);
  }
  if (a.exact_ && b.exact_) {
    return Number::make_exact(WideInt{a.num_} * b.den_ + WideInt{b.num_} * a.den_,
                              WideInt{a.den_} * b.den_);
  }
  return inexact(a.to_double() + b.to_double());
}

Number operator-(const Number& a, const Number& b) {
  return a + (-b);
}

Number operator*(const Number& a, const Number& b) {
  if (a.exact_ && b.exact_) {
    return Number::make_exact(WideInt{a.num_} * b.num_, WideInt{a.den_} * b.den_);
  }
  return inexact(a.to_double() * b.to_double());
}

Number operator/(const Number& a, const Number& b) {
  if (b.exact_ && b.num_ == 0) {
    throw DivisionByZero(fmt::format("{} / 0: division by an exact zero", a.str()));
  }
  if (a.exact_ && b.exact_) {
    return Number::make_exact(WideInt{a.num_} * b.den_, WideInt{a.den_} * b.num_);
  }
  return inexact(a.to_double() / b.to_double());
}

Number Number::operator-() const {
  Number n = *this;
  n.num_ = -n.num_;
  n.value_ = -n.value_;
  return n;
}

Number pow_integer(const Number& a, std::int64_t n) {
  if (n < 0) {
    if (a.is_zero() && a.exact_) {
      throw DivisionByZero(fmt::format("0^{}: division by an exact zero", n));
    }
    return Number(1) / pow_integer(a, -n);
  }
  Number result(1);
  Number base = a;
  while (n > 0) {  // square and multiply; falls back to double on overflow
    if (n & 1) result = result * base;
    n >>= 1;
    if (n > 0) base = base * base;
  }
  return result;
}

std::strong_ordering compare(const Number& a, const Number& b) {
  if (a.exact_ && b.exact_) {
    return WideInt{a.num_} * b.den_ <=> WideInt{b.num_} * a.den_;
  }
  const double x = a.to_double();
  const double y = b.to_double();
  if (x < y) return std::strong_ordering::less;
  if (x > y) return std::strong_ordering::greater;
  if (a.exact_ != b.exact_)
    return a.exact_ ? std::strong_ordering::less : std::strong_ordering::greater;
  // Both inexact and equal in value (NaN never reaches here: constants are finite).
  return std::strong_ordering::equal;
}

std::string Number::str() const {
  if (!exact_) return fmt::format("{}", value_);
  if (den_ == 1) return fmt::format("{}", num_);
  return fmt::format("{}/{}", num_, den_);
}

}  // namespace symdyn::symbolic
