#pragma once
// Expressions of the symbolic engine.
//
// Grammar (every node is immutable and interned: it exists once per Context):
//
//   expr := number                       exact rational p/q, or a finite double
//         | symbol                       a name and a SymbolKind
//         | add(expr, expr, ...)         n-ary sum
//         | mul(expr, expr, ...)         n-ary product
//         | pow(expr, number)            integer, rational or real exponent; sqrt(x) = x^(1/2)
//         | f(expr) | atan2(expr, expr)  f in sin cos tan asin acos atan exp log abs
//
// Because nodes are interned (hash-consed), two expressions are equal exactly
// when they are the same node: `a == b` is a pointer comparison, the hash is
// cached, and shared subexpressions are shared for free.
//
// Canonical form, applied by construction (the smart constructors below are the
// only way to make a node):
//   - sums and products are flattened; their operands are sorted in a structural
//     order (kind, then payload, then operands; symbols by declaration order), so
//     the same expression prints the same however it was built;
//   - like terms are collected (2x + 3x = 5x, x - x = 0), like factors are
//     collected (x·x = x², x·x⁻¹ = 1), numeric coefficients are folded and a
//     numeric coefficient is distributed over a sum (2(a + b) = 2a + 2b);
//   - identities: x + 0 = x, 1·x = x, 0·x = 0, x^0 = 1, x^1 = x,
//     (x^a)^n = x^(a·n) for an integer n, (x·y)^n = x^n·y^n for an integer n;
//   - constants are folded (sin(0) = 0, sqrt(4) = 2, 2^-1 = 1/2; a function of an
//     inexact constant is evaluated in double);
//   - odd and even functions: sin(-x) = -sin(x), tan(-x) = -tan(x), asin(-x) =
//     -asin(x), atan(-x) = -atan(x), cos(-x) = cos(x), abs(-x) = abs(x), where
//     "-x" means x has a negative leading coefficient;
//   - sin, cos and tan of asin, acos and atan in closed form: sin(asin u) = u,
//     cos(asin u) = sin(acos u) = sqrt(1 - u²) (the branch of asin's and acos's
//     ranges), cos(atan u) = 1/sqrt(1 + u²), tan(atan u) = u, and the others
//     as their quotients; a pair of calls becomes arithmetic.
// Combining like factors never shrinks the domain of an expression: x·x⁻¹ = 1
// is the continuous extension at x = 0, and no rule introduces a NaN.
//
// Errors: division by an exact zero throws DivisionByZero; a constant out of a
// function's domain (log(0), asin(2), sqrt(-1)) throws DomainError; a non-finite
// double constant throws DomainError. Nothing silently becomes NaN.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/node_kinds.hpp>
#include <symdyn/symbolic/number.hpp>

namespace symdyn::symbolic {

enum class Kind : std::uint8_t {
#define SYMDYN_KIND_ENUM(kind, name, arity, cpp, cost) kind,
  SYMDYN_FOR_EACH_KIND(SYMDYN_KIND_ENUM)
#undef SYMDYN_KIND_ENUM
};

// Static facts about a kind, read from the table in node_kinds.hpp.
struct KindInfo {
  std::string_view name;
  int arity;  // -1: n-ary
  std::string_view cpp;
  int cost;
};
const KindInfo& info(Kind kind);
bool is_function(Kind kind);  // sin ... abs

// What a symbol stands for. The engine gives the kinds no meaning beyond time
// derivatives (see time_derivative): a Variable's rate is a Rate, whose rate is
// an Acceleration; Time's rate is 1; a Parameter is constant.
enum class SymbolKind : std::uint8_t {
  Variable,      // an independent coordinate, q
  Rate,          // its first time derivative, qd
  Acceleration,  // its second time derivative, qdd
  Dependent,     // an intermediate variable p(q, t)
  DependentRate,
  DependentAcceleration,
  Parameter,  // a constant known only at run time
  Time,
  Intermediate,  // stands for an expression (a definition of compile_program); no time derivative
  Free,          // anything else
};
std::string_view to_string(SymbolKind kind);

class Node;
class Context;

// A value handle to an interned node. Cheap to copy (one pointer); equality is
// identity. Default-constructed, it is the exact zero of the current context.
class Expr {
 public:
  Expr();
  Expr(int value);            // NOLINT(google-explicit-constructor): 2*x reads like math
  Expr(std::int64_t value);   // NOLINT(google-explicit-constructor)
  Expr(double value);         // NOLINT(google-explicit-constructor); throws if not finite
  Expr(const Number& value);  // NOLINT(google-explicit-constructor)
  explicit Expr(const Node* node) : node_(node) {}

  const Node* node() const { return node_; }
  // The accessors are inline (defined after Node): every pass calls them in
  // its innermost loops.
  Kind kind() const;
  std::uint32_t id() const;  // dense per context, in creation order
  std::size_t hash() const;
  std::span<const Expr> args() const;
  Expr arg(std::size_t i) const { return args()[i]; }

  bool is_number() const;  // Rational or Real
  bool is_exact_number() const;
  bool is_zero() const;
  bool is_one() const;
  bool is_symbol() const { return kind() == Kind::Symbol; }
  const Number& number() const;        // throws UsageError unless is_number()
  const std::string& name() const;     // throws UsageError unless is_symbol()
  SymbolKind symbol_kind() const;      // throws UsageError unless is_symbol()
  std::uint32_t symbol_index() const;  // declaration order within the context

  std::string str() const;  // readable infix, see print.hpp

  friend bool operator==(Expr a, Expr b) { return a.node_ == b.node_; }
  friend bool operator!=(Expr a, Expr b) { return a.node_ != b.node_; }

 private:
  [[noreturn]] void throw_not_a(std::string_view what) const;  // UsageError "'<e>' is not a <what>"
  const Node* node_;
};

std::ostream& operator<<(std::ostream& os, Expr e);

// Arithmetic that reads like the math.
Expr operator+(Expr a, Expr b);
Expr operator-(Expr a, Expr b);
Expr operator*(Expr a, Expr b);
Expr operator/(Expr a, Expr b);
Expr operator-(Expr a);
Expr& operator+=(Expr& a, Expr b);
Expr& operator-=(Expr& a, Expr b);
Expr& operator*=(Expr& a, Expr b);
Expr& operator/=(Expr& a, Expr b);

// Smart constructors: the only way to make nodes.
Expr add(std::span<const Expr> terms);
Expr mul(std::span<const Expr> factors);
Expr pow(Expr base, Expr exponent);  // the exponent must be a number
Expr pow(Expr base, int exponent);
Expr sqrt(Expr x);
Expr sin(Expr x);
Expr cos(Expr x);
Expr tan(Expr x);
Expr asin(Expr x);
Expr acos(Expr x);
Expr atan(Expr x);
Expr atan2(Expr y, Expr x);
Expr exp(Expr x);
Expr log(Expr x);
Expr abs(Expr x);
Expr rational(std::int64_t num, std::int64_t den);
// A node of the given kind with the given arguments, through its smart constructor.
Expr make(Kind kind, std::span<const Expr> args);

// Declares a symbol, or returns the one already declared with this name and
// kind. Throws UsageError if the name is declared with another kind.
Expr symbol(std::string_view name, SymbolKind kind = SymbolKind::Free);

// A named intermediate: `symbol` (usually of kind Intermediate) stands for
// `value`. compile_program computes it once instead of substituting it.
struct Definition {
  Expr symbol;
  Expr value;
};

// Structural total order used for canonical forms: numbers < symbols < compound
// nodes; symbols by declaration order; compound nodes by kind, then operands.
// Never by address or hash, so the order is the same in every run.
int compare(Expr a, Expr b);
struct StructuralLess {
  bool operator()(Expr a, Expr b) const { return compare(a, b) < 0; }
};

// "Negative-looking": a negative number, a product with a negative coefficient,
// or a sum whose first term is negative-looking. -x of such an x is not.
bool has_negative_sign(Expr e);

// Splits e into numeric coefficient and the rest: 3·x·y -> (3, x·y); x -> (1, x).
std::pair<Number, Expr> split_coefficient(Expr e);
// Splits e into base and numeric exponent: x^3 -> (x, 3); x -> (x, 1).
std::pair<Expr, Number> split_power(Expr e);

// The interned node. Read-only; made only by the smart constructors.
class Node {
 public:
  Kind kind() const { return kind_; }
  std::uint32_t id() const { return id_; }
  std::size_t hash() const { return hash_; }
  std::span<const Expr> args() const { return {args_, n_args_}; }

 private:
  friend class Expr;
  friend Expr intern_node(Kind kind, std::span<const Expr> args);
  friend Expr intern_number(const Number& value);
  friend Expr symbol(std::string_view name, SymbolKind kind);
  Kind kind_{};
  SymbolKind symbol_kind_{};
  std::uint32_t id_ = 0;
  std::uint32_t n_args_ = 0;
  std::uint32_t symbol_index_ = 0;
  std::size_t hash_ = 0;
  const Expr* args_ = nullptr;
  Number number_;
  const std::string* name_ = nullptr;
};

inline Kind Expr::kind() const {
  return node_->kind();
}
inline std::uint32_t Expr::id() const {
  return node_->id();
}
inline std::size_t Expr::hash() const {
  return node_->hash();
}
inline std::span<const Expr> Expr::args() const {
  return node_->args();
}
inline bool Expr::is_number() const {
  return kind() == Kind::Rational || kind() == Kind::Real;
}
inline bool Expr::is_exact_number() const {
  return kind() == Kind::Rational;
}
inline bool Expr::is_zero() const {
  return is_number() && node_->number_.is_zero();
}
inline bool Expr::is_one() const {
  return is_number() && node_->number_.is_one();
}
inline const Number& Expr::number() const {
  if (!is_number()) throw_not_a("number");
  return node_->number_;
}
inline const std::string& Expr::name() const {
  if (!is_symbol()) throw_not_a("symbol");
  return *node_->name_;
}
inline SymbolKind Expr::symbol_kind() const {
  if (!is_symbol()) throw_not_a("symbol");
  return node_->symbol_kind_;
}
inline std::uint32_t Expr::symbol_index() const {
  if (!is_symbol()) throw_not_a("symbol");
  return node_->symbol_index_;
}

// Owns the nodes (an arena: no reference counts, no recursive destruction of
// deep DAGs) and the table that interns them. Expressions from different
// contexts must not be mixed.
//
// The engine works in the current context: a process-wide default one, or the
// innermost Context::Scope. Tests use a scope per case to start from nothing.
class Context {
 public:
  Context();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  static Context& current();
  std::size_t size() const;  // number of distinct nodes
  std::size_t symbol_count() const;
  std::size_t memory_bytes() const;  // arena and table footprint

  // Makes `context` current for the lifetime of the scope.
  class Scope {
   public:
    explicit Scope(Context& context);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Context* previous_;
  };

 private:
  friend Expr intern_node(Kind kind, std::span<const Expr> args);
  friend Expr intern_number(const Number& value);
  friend Expr symbol(std::string_view name, SymbolKind kind);
  friend class Expr;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Interns a node as given, with no canonicalization. For the smart
// constructors only.
Expr intern_node(Kind kind, std::span<const Expr> args);
Expr intern_number(const Number& value);

}  // namespace symdyn::symbolic

template <>
struct std::hash<symdyn::symbolic::Expr> {
  std::size_t operator()(symdyn::symbolic::Expr e) const noexcept { return e.hash(); }
};
