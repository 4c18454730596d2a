// Smart constructors: canonicalize, then intern. See expr.hpp for the rules.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {
namespace {

Expr number(const Number& n) {
  return intern_number(n);
}

// Operands kept on the stack while a sum or product is built; more go to the heap.
constexpr std::size_t kInlineOperands = 8;

// Collects (key, numeric weight) pairs, summing the weights of equal keys and
// keeping the keys in first-seen order. Used for terms of a sum (key: monomial,
// weight: coefficient) and factors of a product (key: base, weight: exponent).
class Collector {
 public:
  struct Entry {
    Expr key;
    Number weight;
  };

  void add(Expr key, const Number& weight) {
    const std::size_t i = position(key);
    if (i == entries_.size()) {
      entries_.push_back({key, weight});
    } else {
      entries_[i].weight = entries_[i].weight + weight;
    }
  }
  explicit Collector(std::size_t expected) { entries_.reserve(expected); }

  // Entries with a non-zero weight, in structural order of their keys (the
  // keys are distinct, so the order is total). Consumes the collector.
  std::span<const Entry> sorted() {
    Entry* kept = std::remove_if(entries_.begin(), entries_.end(),
                                 [](const Entry& e) { return e.weight.is_zero(); });
    entries_.truncate(static_cast<std::size_t>(kept - entries_.begin()));
    std::sort(entries_.begin(), entries_.end(),
              [](const Entry& x, const Entry& y) { return compare(x.key, y.key) < 0; });
    return entries_;
  }

 private:
  // Where key is among the entries (entries_.size() if absent). Most sums and
  // products have a few operands: scanning them beats hashing; a long sum
  // gets an index.
  std::size_t position(Expr key) {
    constexpr std::size_t kScanned = 16;
    if (entries_.size() < kScanned) {
      for (std::size_t i = 0; i < entries_.size(); ++i) {
        if (entries_[i].key == key) return i;
      }
      return entries_.size();
    }
    if (index_.empty()) {
      for (std::size_t i = 0; i < entries_.size(); ++i) index_.emplace(entries_[i].key.node(), i);
    }
    return index_.try_emplace(key.node(), entries_.size()).first->second;
  }

  detail::SmallVector<Entry, kInlineOperands> entries_;
  std::unordered_map<const Node*, std::size_t> index_;
};

// coefficient · monomial, where the monomial is not a number and carries no
// coefficient of its own.
Expr scale(const Number& coefficient, Expr monomial) {
  if (coefficient.is_one()) return monomial;
  if (coefficient.is_zero()) return number(Number(0));
  detail::SmallVector<Expr, kInlineOperands> factors;
  factors.reserve(1 + monomial.args().size());
  factors.push_back(number(coefficient));
  if (monomial.kind() == Kind::Mul) {
    for (Expr f : monomial.args()) factors.push_back(f);
  } else {
    factors.push_back(monomial);
  }
  return intern_node(Kind::Mul, factors);
}

// Exact k-th root of a non-negative integer, if there is one.
bool exact_root(std::int64_t value, std::int64_t k, std::int64_t* root) {
  if (value < 0) return false;
  const auto guess = static_cast<std::int64_t>(
      std::llround(std::pow(static_cast<double>(value), 1.0 / static_cast<double>(k))));
  for (std::int64_t r = std::max<std::int64_t>(0, guess - 1); r <= guess + 1; ++r) {
    Number p = pow_integer(Number(r), k);
    if (p.is_exact() && p.num() == value) {
      *root = r;
      return true;
    }
  }
  return false;
}

// base^exponent for numbers; returns false when it must stay symbolic
// (an irrational root such as 2^(1/2)).
bool fold_power(const Number& base, const Number& exponent, Number* out) {
  if (exponent.is_integer()) {
    *out = pow_integer(base, exponent.num());
    return true;
  }
  if (base.is_exact() && exponent.is_exact()) {
    if (base.is_negative()) {
      throw DomainError(fmt::format("({})^({}): negative base with a fractional exponent",
                                    base.str(), exponent.str()));
    }
    std::int64_t rn = 0;
    std::int64_t rd = 0;
    if (exact_root(base.num(), exponent.den(), &rn) &&
        exact_root(base.den(), exponent.den(), &rd)) {
      *out = pow_integer(Number(rn, rd), exponent.num());
      return true;
    }
    return false;
  }
  const double b = base.to_double();
  const double value = std::pow(b, exponent.to_double());
  if (!std::isfinite(value)) {
    throw DomainError(
        fmt::format("({})^({}) is not a finite real number", base.str(), exponent.str()));
  }
  *out = Number::from_double(value);
  return true;
}

}  // namespace

std::pair<Number, Expr> split_coefficient(Expr e) {
  if (e.kind() == Kind::Mul && e.arg(0).is_number()) {
    const auto rest = e.args().subspan(1);
    return {e.arg(0).number(), rest.size() == 1 ? rest[0] : intern_node(Kind::Mul, rest)};
  }
  return {Number(1), e};
}

std::pair<Expr, Number> split_power(Expr e) {
  if (e.kind() == Kind::Pow) return {e.arg(0), e.arg(1).number()};
  return {e, Number(1)};
}

bool has_negative_sign(Expr e) {
  switch (e.kind()) {
    case Kind::Rational:
    case Kind::Real:
      return e.number().is_negative();
    case Kind::Mul:
      return e.arg(0).is_number() && e.arg(0).number().is_negative();
    case Kind::Add: {
      const auto args = e.args();
      // The constant term sorts first; the sign is that of the first non-constant term.
      return has_negative_sign(args[0].is_number() ? args[1] : args[0]);
    }
    default:
      return false;
  }
}

Expr add(std::span<const Expr> terms) {
  Number constant(0);
  Collector collector(terms.size());
  auto take = [&](Expr t) {
    if (t.is_number()) {
      constant = constant + t.number();
    } else {
      auto [c, m] = split_coefficient(t);
      collector.add(m, c);
    }
  };
  for (Expr t : terms) {
    if (t.kind() == Kind::Add) {
      for (Expr u : t.args()) take(u);
    } else {
      take(t);
    }
  }
  detail::SmallVector<Expr, kInlineOperands> out;
  const auto collected = collector.sorted();
  out.reserve(1 + collected.size());
  if (!constant.is_zero()) out.push_back(number(constant));
  for (const auto& [m, c] : collected) out.push_back(scale(c, m));
  if (out.empty()) return number(Number(0));
  if (out.size() == 1) return out[0];
  return intern_node(Kind::Add, out);
}

Expr mul(std::span<const Expr> factors) {
  Number coefficient(1);
  Collector collector(factors.size());
  auto take = [&](Expr f) {
    if (f.is_number()) {
      coefficient = coefficient * f.number();
    } else {
      auto [b, e] = split_power(f);
      collector.add(b, e);
    }
  };
  for (Expr f : factors) {
    if (f.kind() == Kind::Mul) {
      for (Expr g : f.args()) take(g);
    } else {
      take(f);
    }
  }
  if (coefficient.is_zero()) return number(Number(0));
  detail::SmallVector<Expr, kInlineOperands> rest;
  for (const auto& [b, e] : collector.sorted()) rest.push_back(e.is_one() ? b : pow(b, Expr(e)));
  // pow may have folded a factor into a number (sqrt(2)·sqrt(2) = 2) or a product.
  if (std::any_of(rest.begin(), rest.end(),
                  [](Expr f) { return f.is_number() || f.kind() == Kind::Mul; })) {
    rest.push_back(number(coefficient));
    return mul(rest);
  }
  if (rest.empty()) return number(coefficient);
  // Distribute a numeric coefficient over a lone sum: 2(a + b) = 2a + 2b.
  if (rest.size() == 1 && rest[0].kind() == Kind::Add && !coefficient.is_one()) {
    std::vector<Expr> terms;
    for (Expr t : rest[0].args()) {
      auto [c, m] = split_coefficient(t);
      terms.push_back(m.is_number() ? number(c * coefficient * m.number())
                                    : scale(c * coefficient, m));
    }
    return add(terms);
  }
  if (rest.size() == 1 && coefficient.is_one()) return rest[0];
  if (rest.size() == 1) return scale(coefficient, rest[0]);
  Expr monomial = intern_node(Kind::Mul, rest);
  return scale(coefficient, monomial);
}

Expr pow(Expr base, Expr exponent) {
  if (!exponent.is_number()) {
    throw UsageError(
        fmt::format("pow({}, {}): the exponent must be a number", base.str(), exponent.str()));
  }
  const Number& e = exponent.number();
  if (e.is_zero()) return number(Number(1));
  if (e.is_one()) return base;
  if (base.is_number()) {
    Number folded;
    if (fold_power(base.number(), e, &folded)) return number(folded);
    return intern_node(Kind::Pow, std::array{base, exponent});
  }
  if (e.is_integer()) {
    // (x^a)^n = x^(a·n): exact for an integer n, whatever a.
    if (base.kind() == Kind::Pow) return pow(base.arg(0), Expr(base.arg(1).number() * e));
    // (x·y)^n = x^n·y^n
    if (base.kind() == Kind::Mul) {
      std::vector<Expr> factors;
      for (Expr f : base.args()) factors.push_back(pow(f, exponent));
      return mul(factors);
    }
  }
  if (base.kind() == Kind::Pow && base.arg(1).number().is_integer() &&
      base.arg(1).number().num() % 2 != 0) {
    // (x^odd)^a = x^(odd·a) holds for every real x where the left side is real.
    return pow(base.arg(0), Expr(base.arg(1).number() * e));
  }
  return intern_node(Kind::Pow, std::array{base, number(e)});
}

Expr pow(Expr base, int exponent) {
  return pow(base, Expr(exponent));
}
Expr sqrt(Expr x) {
  return pow(x, rational(1, 2));
}
Expr rational(std::int64_t num, std::int64_t den) {
  return number(Number(num, den));
}

namespace {

// A function of a constant: exact where the value is a known rational, a double
// otherwise. Throws DomainError outside the function's real domain.
Expr fold_function(Kind kind, double x, double (*f)(double), bool in_domain) {
  if (!in_domain) {
    throw DomainError(
        fmt::format("{}({}) is outside the function's real domain", info(kind).name, x));
  }
  const double value = f(x);
  return Expr(value);
}

double sin_d(double x) {
  return std::sin(x);
}
double cos_d(double x) {
  return std::cos(x);
}
double tan_d(double x) {
  return std::tan(x);
}
double asin_d(double x) {
  return std::asin(x);
}
double acos_d(double x) {
  return std::acos(x);
}
double atan_d(double x) {
  return std::atan(x);
}
double exp_d(double x) {
  return std::exp(x);
}
double log_d(double x) {
  return std::log(x);
}

// f(-x) = -f(x)
Expr odd(Kind kind, Expr x, Expr (*f)(Expr)) {
  if (has_negative_sign(x)) return -f(-x);
  return intern_node(kind, std::array{x});
}

// sqrt(1 - u²) and sqrt(1 + u²): the cosine of asin u (the sine of acos u),
// and the secant of atan u. The square root is the right branch: asin's range
// [-π/2, π/2] has cos >= 0, acos's [0, π] has sin >= 0, atan's cos > 0.
Expr sqrt_one_minus_square(Expr u) {
  return sqrt(1 - u * u);
}
Expr sqrt_one_plus_square(Expr u) {
  return sqrt(1 + u * u);
}

// sin, cos or tan of an inverse function of u, in closed form (false when x
// is no inverse function): a call pair becomes arithmetic, and
// the domain never shrinks (asin u, acos u need |u| <= 1 on both sides).
//   sin(asin u) = u               cos(asin u) = sqrt(1 - u²)   tan(asin u) = u / sqrt(1 - u²)
//   sin(acos u) = sqrt(1 - u²)    cos(acos u) = u              tan(acos u) = sqrt(1 - u²) / u
//   sin(atan u) = u / sqrt(1 + u²) cos(atan u) = 1 / sqrt(1 + u²) tan(atan u) = u
bool of_inverse(Kind f, Expr x, Expr* out) {
  if (x.kind() != Kind::Asin && x.kind() != Kind::Acos && x.kind() != Kind::Atan) return false;
  const Expr u = x.arg(0);
  Expr s, c;  // the sine and cosine of x
  switch (x.kind()) {
    case Kind::Asin:
      s = u, c = sqrt_one_minus_square(u);
      break;
    case Kind::Acos:
      s = sqrt_one_minus_square(u), c = u;
      break;
    default:
      s = u / sqrt_one_plus_square(u), c = 1 / sqrt_one_plus_square(u);
      break;
  }
  switch (f) {
    case Kind::Sin:
      *out = s;
      break;
    case Kind::Cos:
      *out = c;
      break;
    default:
      *out = x.kind() == Kind::Atan ? u : s / c;
      break;
  }
  return true;
}

}  // namespace

Expr sin(Expr x) {
  if (x.is_zero()) return Expr(0);
  if (x.is_number()) return fold_function(Kind::Sin, x.number().to_double(), sin_d, true);
  if (Expr r; of_inverse(Kind::Sin, x, &r)) return r;
  return odd(Kind::Sin, x, sin);
}

Expr cos(Expr x) {
  if (x.is_zero()) return Expr(1);
  if (x.is_number()) return fold_function(Kind::Cos, x.number().to_double(), cos_d, true);
  if (Expr r; of_inverse(Kind::Cos, x, &r)) return r;
  if (has_negative_sign(x)) return cos(-x);
  return intern_node(Kind::Cos, std::array{x});
}

Expr tan(Expr x) {
  if (x.is_zero()) return Expr(0);
  if (x.is_number()) return fold_function(Kind::Tan, x.number().to_double(), tan_d, true);
  if (Expr r; of_inverse(Kind::Tan, x, &r)) return r;
  return odd(Kind::Tan, x, tan);
}

Expr asin(Expr x) {
  if (x.is_zero()) return Expr(0);
  if (x.is_number()) {
    const double v = x.number().to_double();
    return fold_function(Kind::Asin, v, asin_d, v >= -1.0 && v <= 1.0);
  }
  return odd(Kind::Asin, x, asin);
}

Expr acos(Expr x) {
  if (x.is_one()) return Expr(0);
  if (x.is_number()) {
    const double v = x.number().to_double();
    return fold_function(Kind::Acos, v, acos_d, v >= -1.0 && v <= 1.0);
  }
  return intern_node(Kind::Acos, std::array{x});
}

Expr atan(Expr x) {
  if (x.is_zero()) return Expr(0);
  if (x.is_number()) return fold_function(Kind::Atan, x.number().to_double(), atan_d, true);
  return odd(Kind::Atan, x, atan);
}

Expr atan2(Expr y, Expr x) {
  if (y.is_number() && x.is_number()) {
    const double yv = y.number().to_double();
    const double xv = x.number().to_double();
    if (yv == 0.0 && xv == 0.0) throw DomainError("atan2(0, 0) is undefined");
    if (yv == 0.0 && xv > 0.0) return Expr(0);
    return Expr(std::atan2(yv, xv));
  }
  return intern_node(Kind::Atan2, std::array{y, x});
}

Expr exp(Expr x) {
  if (x.is_zero()) return Expr(1);
  if (x.is_number()) return fold_function(Kind::Exp, x.number().to_double(), exp_d, true);
  if (x.kind() == Kind::Log) return x.arg(0);
  return intern_node(Kind::Exp, std::array{x});
}

Expr log(Expr x) {
  if (x.is_one()) return Expr(0);
  if (x.is_number()) {
    const double v = x.number().to_double();
    return fold_function(Kind::Log, v, log_d, v > 0.0);
  }
  if (x.kind() == Kind::Exp) return x.arg(0);
  return intern_node(Kind::Log, std::array{x});
}

Expr abs(Expr x) {
  if (x.is_number()) {
    const Number& n = x.number();
    return n.is_negative() ? Expr(-n) : x;
  }
  if (x.kind() == Kind::Abs) return x;
  if (has_negative_sign(x)) return abs(-x);
  return intern_node(Kind::Abs, std::array{x});
}

Expr make(Kind kind, std::span<const Expr> args) {
  switch (kind) {
    case Kind::Add:
      return add(args);
    case Kind::Mul:
      return mul(args);
    case Kind::Pow:
      return pow(args[0], args[1]);
    case Kind::Sin:
      return sin(args[0]);
    case Kind::Cos:
      return cos(args[0]);
    case Kind::Tan:
      return tan(args[0]);
    case Kind::Asin:
      return asin(args[0]);
    case Kind::Acos:
      return acos(args[0]);
    case Kind::Atan:
      return atan(args[0]);
    case Kind::Atan2:
      return atan2(args[0], args[1]);
    case Kind::Exp:
      return exp(args[0]);
    case Kind::Log:
      return log(args[0]);
    case Kind::Abs:
      return abs(args[0]);
    default:
      throw UsageError(fmt::format("make: '{}' is a leaf kind", info(kind).name));
  }
}

Expr operator+(Expr a, Expr b) {
  return add(std::array{a, b});
}
Expr operator-(Expr a, Expr b) {
  return add(std::array{a, -b});
}
Expr operator*(Expr a, Expr b) {
  return mul(std::array{a, b});
}
Expr operator/(Expr a, Expr b) {
  if (b.is_zero() && b.is_exact_number()) {
    throw DivisionByZero(fmt::format("({}) / 0: division by an exact zero", a.str()));
  }
  return mul(std::array{a, pow(b, -1)});
}
Expr operator-(Expr a) {
  return mul(std::array{Expr(-1), a});
}
Expr& operator+=(Expr& a, Expr b) {
  return a = a + b;
}
Expr& operator-=(Expr& a, Expr b) {
  return a = a - b;
}
Expr& operator*=(Expr& a, Expr b) {
  return a = a * b;
}
Expr& operator/=(Expr& a, Expr b) {
  return a = a / b;
}

}  // namespace symdyn::symbolic
