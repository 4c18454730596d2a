#pragma once
// The value of every node kind for any scalar type: double, long double,
// std::complex<double> (complex step) or anything with the same functions.
// One definition serves the DAG evaluator and the program interpreter.

#include <cmath>
#include <complex>
#include <span>

#include "symbolic/expr.hpp"

namespace symdyn::symbolic::scalar {

template <class S>
struct IsComplex : std::false_type {};
template <class T>
struct IsComplex<std::complex<T>> : std::true_type {};

// |x| and atan2 on the real axis, extended analytically for the complex step:
// abs(x) = x·sign(Re x), atan2(y, x) = atan(y/x) + the real branch offset.
template <class S>
S abs(const S& x) {
  if constexpr (IsComplex<S>::value) {
    return x.real() < 0 ? -x : x;
  } else {
    using std::abs;
    return abs(x);
  }
}

template <class S>
S atan2(const S& y, const S& x) {
  if constexpr (IsComplex<S>::value) {
    using T = typename S::value_type;
    const T offset = std::atan2(y.real(), x.real()) - std::atan(y.real() / x.real());
    return std::atan(y / x) + S(offset);
  } else {
    using std::atan2;
    return atan2(y, x);
  }
}

// x^e with a numeric exponent: products for small integers (exact and fast),
// sqrt for halves, pow otherwise. A complex x takes products (by squaring) for
// every integer exponent: complex pow goes through log, and for a negative real
// part the rounding of exp(i·n·π) swamps the 1e-30 imaginary part of a
// complex step.
template <class S>
S power(const S& x, const Number& e) {
  using std::pow;
  using std::sqrt;
  if (e.is_integer() && e.num() >= -4 && e.num() <= 4) {
    const std::int64_t n = e.num() < 0 ? -e.num() : e.num();
    S r = S(1);
    for (std::int64_t i = 0; i < n; ++i) r = r * x;
    return e.num() < 0 ? S(1) / r : r;
  }
  if (IsComplex<S>::value && e.is_integer()) {
    S r = S(1);
    S square = x;
    for (std::int64_t n = e.num() < 0 ? -e.num() : e.num(); n > 0; n /= 2) {
      if (n % 2 == 1) r = r * square;
      square = square * square;
    }
    return e.num() < 0 ? S(1) / r : r;
  }
  if (e.is_exact() && e.den() == 2) {
    const S root = sqrt(x);
    return power(x, e - Number(1, 2)) * root;
  }
  return pow(x, static_cast<typename std::conditional_t<IsComplex<S>::value, S, S>>(e.to_double()));
}

// The value of a function node of the given kind.
template <class S>
S call(Kind kind, std::span<const S> a) {
  using std::acos;
  using std::asin;
  using std::atan;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::tan;
  switch (kind) {
    case Kind::Sin: return sin(a[0]);
    case Kind::Cos: return cos(a[0]);
    case Kind::Tan: return tan(a[0]);
    case Kind::Asin: return asin(a[0]);
    case Kind::Acos: return acos(a[0]);
    case Kind::Atan: return atan(a[0]);
    case Kind::Atan2: return scalar::atan2(a[0], a[1]);
    case Kind::Exp: return exp(a[0]);
    case Kind::Log: return log(a[0]);
    case Kind::Abs: return scalar::abs(a[0]);  // qualified: ADL would pick std::abs(complex), a real
    default: throw UsageError("scalar::call: not a function kind");
  }
}

}  // namespace symdyn::symbolic::scalar
