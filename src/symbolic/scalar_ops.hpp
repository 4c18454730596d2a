#pragma once
// The value of every node kind for any scalar type: double, long double,
// std::complex<double> (complex step) or anything with the same functions.
// One definition serves the DAG evaluator and the program interpreter.

#include <cmath>
#include <complex>
#include <span>

#include <symdyn/symbolic/expr.hpp>

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

// x^n for an integer n, by repeated squaring: x^(2m) = (x^m)^2,
// x^(2m+1) = x^(2m)·x. The program (program.hpp) lowers integer powers into the
// same multiplications, so both give the same rounding; and unlike pow, the
// result stays exact in the complex step at a negative base.
template <class S>
S integer_power(const S& x, std::int64_t n) {
  if (n < 0) return S(1) / integer_power(x, -n);
  if (n == 0) return S(1);
  if (n == 1) return x;
  if (n % 2 == 0) {
    const S half = integer_power(x, n / 2);
    return half * half;
  }
  return integer_power(x, n - 1) * x;
}

// Largest |n| for which x^n is computed by multiplications rather than pow.
inline constexpr std::int64_t kMaxMultipliedPower = 32;

// x^e with a numeric exponent: multiplications for integers up to
// kMaxMultipliedPower, sqrt for halves, pow otherwise.
template <class S>
S power(const S& x, const Number& e) {
  using std::pow;
  using std::sqrt;
  // Complex integer powers always multiply: complex pow goes through log, and for
  // a negative real part its rounding swamps the 1e-30 imaginary part of a complex step.
  const bool multiply =
      IsComplex<S>::value || (e.num() >= -kMaxMultipliedPower && e.num() <= kMaxMultipliedPower);
  if (e.is_integer() && multiply) return integer_power(x, e.num());
  if (e.is_exact() && e.den() == 2 && e.num() >= -2 * kMaxMultipliedPower &&
      e.num() <= 2 * kMaxMultipliedPower) {
    // x^(k/2) = x^((k-1)/2)·sqrt(x), and 1/x^(|k|/2) for a negative k.
    if (e.is_negative()) return S(1) / power(x, -e);
    return integer_power(x, (e.num() - 1) / 2) * sqrt(x);
  }
  return pow(x, S(e.to_double()));
}

// The value of the function kind K, for callers that know the kind at compile
// time (the program interpreter). `b` is atan2's second argument, ignored by
// the other kinds.
template <Kind K, class S>
S apply(const S& a, [[maybe_unused]] const S& b) {
  using std::acos;
  using std::asin;
  using std::atan;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::tan;
  if constexpr (K == Kind::Sin)
    return sin(a);
  else if constexpr (K == Kind::Cos)
    return cos(a);
  else if constexpr (K == Kind::Tan)
    return tan(a);
  else if constexpr (K == Kind::Asin)
    return asin(a);
  else if constexpr (K == Kind::Acos)
    return acos(a);
  else if constexpr (K == Kind::Atan)
    return atan(a);
  else if constexpr (K == Kind::Atan2)
    return scalar::atan2(a, b);
  else if constexpr (K == Kind::Exp)
    return exp(a);
  else if constexpr (K == Kind::Log)
    return log(a);
  else if constexpr (K == Kind::Abs)
    return scalar::abs(a);
  else
    static_assert(K == Kind::Sin, "apply: not a function kind");
}

// The value of a function node of the given kind.
template <class S>
S call(Kind kind, std::span<const S> a) {
  switch (kind) {
#define SYMDYN_SCALAR_CALL(k, name, arity, ...) \
  case Kind::k:                                 \
    return apply<Kind::k>(a[0], a[arity - 1]);
    SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_SCALAR_CALL)
#undef SYMDYN_SCALAR_CALL
    default:
      throw UsageError("scalar::call: not a function kind");
  }
}

}  // namespace symdyn::symbolic::scalar
