#include <fmt/format.h>

#include <ostream>

#include <symdyn/symbolic/print.hpp>

namespace symdyn::symbolic {
namespace {

// Binding strength, for minimal parentheses.
enum Precedence { kSum = 1, kProduct = 2, kUnary = 3, kPower = 4, kAtom = 5 };

class Printer {
 public:
  Printer(bool cpp, const SymbolNamer& name_of) : cpp_(cpp), name_of_(name_of) {}

  // Prints e, parenthesized if it binds weaker than `context`.
  std::string print(Expr e, int context = kSum) {
    int prec = kAtom;
    std::string s = print_bare(e, &prec);
    return prec < context ? fmt::format("({})", s) : s;
  }

 private:
  std::string print_bare(Expr e, int* prec) {
    switch (e.kind()) {
      case Kind::Rational:
      case Kind::Real:
        return print_number(e.number(), prec);
      case Kind::Symbol:
        return name_of_ ? name_of_(e) : e.name();
      case Kind::Add:
        *prec = kSum;
        return print_sum(e);
      case Kind::Mul:
        return print_product(e, prec);
      case Kind::Pow:
        return print_power(e.arg(0), e.arg(1).number(), prec);
      default:
        return print_call(e);
    }
  }

  std::string print_number(const Number& n, int* prec) {
    if (n.is_negative()) *prec = kUnary;
    if (!cpp_) {
      if (n.is_exact() && n.den() != 1) *prec = n.is_negative() ? kUnary : kProduct;
      return n.str();
    }
    return cpp_literal(n.to_double());
  }

  std::string print_sum(Expr e) {
    std::string out;
    for (Expr term : e.args()) {
      if (out.empty()) {
        out = print(term, kSum);
      } else if (has_negative_sign(term)) {
        out += fmt::format(" - {}", print(-term, kProduct));
      } else {
        out += fmt::format(" + {}", print(term, kProduct));
      }
    }
    return out;
  }

  // Numerator factors (positive powers) over denominator factors (negative ones).
  std::string print_product(Expr e, int* prec) {
    auto [coefficient, rest] = split_coefficient(e);
    if (coefficient.is_negative()) {
      *prec = kUnary;
      Expr positive = -e;
      return fmt::format("-{}", print(positive, kProduct));
    }
    *prec = kProduct;
    std::vector<std::string> num;
    std::vector<std::string> den;
    if (!coefficient.is_one()) {
      if (coefficient.is_exact() && !cpp_) {
        if (coefficient.num() != 1) num.push_back(fmt::format("{}", coefficient.num()));
        if (coefficient.den() != 1) den.push_back(fmt::format("{}", coefficient.den()));
      } else {
        num.push_back(cpp_literal(coefficient.to_double()));
      }
    }
    const auto factors = rest.kind() == Kind::Mul ? rest.args() : std::span<const Expr>(&rest, 1);
    for (Expr f : factors) {
      auto [base, exponent] = split_power(f);
      if (exponent.is_negative()) {
        den.push_back(exponent == Number(-1) ? print(base, kPower)
                                             : print_power_string(base, -exponent));
      } else {
        num.push_back(print(f, kProduct));
      }
    }
    std::string out = num.empty() ? (cpp_ ? "1.0" : "1") : fmt::format("{}", fmt::join(num, "*"));
    if (den.size() == 1) out += fmt::format("/{}", den[0]);
    if (den.size() > 1) out += fmt::format("/({})", fmt::join(den, "*"));
    return out;
  }

  // base^exponent printed as an operand of a division.
  std::string print_power_string(Expr base, const Number& exponent) {
    int prec = kAtom;
    std::string s = print_power(base, exponent, &prec);
    return prec < kPower ? fmt::format("({})", s) : s;
  }

  std::string print_power(Expr base, const Number& exponent, int* prec) {
    if (exponent == Number(1, 2)) return call("sqrt", {base});
    if (exponent.is_negative()) {
      *prec = kProduct;
      return fmt::format("{}/{}", cpp_ ? "1.0" : "1", print_power_string(base, -exponent));
    }
    if (!cpp_) {
      *prec = kPower;
      const bool atom = exponent.is_integer() && !exponent.is_negative();
      const std::string e = atom ? exponent.str() : fmt::format("({})", exponent.str());
      return fmt::format("{}^{}", print(base, kPower + 1), e);
    }
    if (exponent.is_integer() && exponent.num() <= 4) {
      *prec = kProduct;
      const std::string b = print(base, kPower);
      std::string out = b;
      for (std::int64_t i = 1; i < exponent.num(); ++i) out += fmt::format("*{}", b);
      return out;
    }
    if (exponent.is_exact() && exponent.den() == 2) {
      *prec = kProduct;
      Number whole = exponent - Number(1, 2);  // x^(k+1/2) = x^k·sqrt(x)
      return fmt::format("{}*{}", print_power(base, whole, prec), call("sqrt", {base}));
    }
    return fmt::format("std::pow({}, {})", print(base), cpp_literal(exponent.to_double()));
  }

  std::string print_call(Expr e) {
    std::vector<Expr> args(e.args().begin(), e.args().end());
    const std::string_view name = cpp_ ? info(e.kind()).cpp : info(e.kind()).name;
    return call(name, args);
  }

  std::string call(std::string_view name, const std::vector<Expr>& args) {
    std::vector<std::string> parts;
    for (Expr a : args) parts.push_back(print(a, kSum));
    const bool qualify = cpp_ && name.find("::") == std::string_view::npos;
    const std::string fn = fmt::format("{}{}", qualify ? "std::" : "", name);
    return fmt::format("{}({})", fn, fmt::join(parts, ", "));
  }

  bool cpp_;
  const SymbolNamer& name_of_;
};

}  // namespace

std::string cpp_literal(double value) {
  std::string s = fmt::format("{}", value);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string to_infix(Expr e) {
  static const SymbolNamer none;
  return Printer(false, none).print(e);
}

std::string to_cpp(Expr e, const SymbolNamer& name_of) {
  return Printer(true, name_of).print(e);
}

std::string Expr::str() const {
  return to_infix(*this);
}

std::ostream& operator<<(std::ostream& os, Expr e) {
  return os << to_infix(e);
}

}  // namespace symdyn::symbolic
