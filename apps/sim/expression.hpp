#pragma once
// Expressions of scenario files: force laws, references, output channels and
// checks, written as text ("clamp(50 * (5 - chassis.ux), -100, 100)").
//
// Grammar (usual precedence, ^ binds tightest and to the right):
//   expr    := term (('+' | '-') term)*
//   term    := unary (('*' | '/') unary)*
//   unary   := '-' unary | power
//   power   := primary ('^' unary)?
//   primary := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
// Names are letters, digits, '_' and '.', starting with a letter or '_'. The
// functions of the table in expression.cpp (sin, clamp, ...) and the constant
// pi are built in; every other name, and calls the table does not know, are
// resolved once, when the text is parsed, by the caller's Resolver (a scenario
// knows coordinates, bodies, force elements, statistics). Evaluation reads
// the resolved symbols through an Environment and allocates nothing.

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace symdyn::sim {

// A text that does not parse, or a name the resolver refuses: the message
// says where (column) and what was expected.
class ExpressionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Gives the value of a resolved symbol at the current instant.
class Environment {
 public:
  virtual ~Environment() = default;
  virtual double value(int symbol) const = 0;
};

struct Resolver {
  // The symbol a name stands for; throws ExpressionError naming the valid ones.
  std::function<int(std::string_view name)> symbol;
  // A call the built-in table does not know: a symbol, or -1 to refuse it.
  // Receives the argument texts, unparsed.
  std::function<int(std::string_view function, const std::vector<std::string_view>& arguments)>
      call;
};

class Expression {
 public:
  Expression() = default;
  // Throws ExpressionError.
  static Expression parse(std::string_view text, const Resolver& resolver);
  // A number: the expression of that constant.
  static Expression constant(double value);

  double evaluate(const Environment& env) const;
  // The value, and in gradient (symbols().size()) its derivatives with respect
  // to the symbols, in the order of symbols(): exact, by forward mode through
  // the program; where a function switches (abs, min, max, clamp) those of the
  // branch the value takes, sign and step flat.
  double evaluate(const Environment& env, double* gradient) const;
  const std::string& text() const { return text_; }
  // The symbols it reads (each once), for the caller to know what to compute.
  const std::vector<int>& symbols() const { return symbols_; }
  bool empty() const { return ops_.empty(); }

  // One instruction of the stack program: push a number or a symbol, or
  // apply a function of the table to the top `arity` entries.
  struct Op {
    enum class Kind { number, symbol, function } kind = Kind::number;
    double number = 0.0;
    int symbol = 0;
    int slot = 0;  // a symbol's place in symbols()
    double (*function)(const double* arguments) = nullptr;
    void (*partials)(const double* arguments, double* derivatives) = nullptr;
    int arity = 0;
  };

 private:
  std::string text_;
  std::vector<Op> ops_;
  std::vector<int> symbols_;
  std::shared_ptr<std::vector<double>> stack_;  // sized when parsed
  // Forward mode's stack: each entry's gradient (a row of symbols().size()) and
  // whether it varies.
  struct Gradients {
    std::vector<double> rows;
    std::vector<char> varies;
  };
  std::shared_ptr<Gradients> gradients_;
};

}  // namespace symdyn::sim
