#include "expression.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

namespace symdyn::sim {

namespace {

// The built-in functions, one row each: name, arity, value and its partial
// derivatives d[i] = ∂f/∂a[i]. Where a law switches (abs, min, max, clamp) they
// are those of the branch the value takes; sign and step are flat.
struct Function {
  const char* name;
  int arity;
  double (*value)(const double* a);
  void (*partials)(const double* a, double* d);
};

constexpr int kMaxArity = 3;

constexpr Function kFunctions[] = {
    {"neg", 1, [](const double* a) { return -a[0]; },
     [](const double*, double* d) { d[0] = -1.0; }},
    {"+", 2, [](const double* a) { return a[0] + a[1]; },
     [](const double*, double* d) { d[0] = d[1] = 1.0; }},
    {"-", 2, [](const double* a) { return a[0] - a[1]; },
     [](const double*, double* d) {
       d[0] = 1.0;
       d[1] = -1.0;
     }},
    {"*", 2, [](const double* a) { return a[0] * a[1]; },
     [](const double* a, double* d) {
       d[0] = a[1];
       d[1] = a[0];
     }},
    {"/", 2, [](const double* a) { return a[0] / a[1]; },
     [](const double* a, double* d) {
       d[0] = 1.0 / a[1];
       d[1] = -a[0] / (a[1] * a[1]);
     }},
    {"^", 2, [](const double* a) { return std::pow(a[0], a[1]); },
     [](const double* a, double* d) {
       d[0] = a[1] * std::pow(a[0], a[1] - 1.0);
       d[1] = std::pow(a[0], a[1]) * std::log(a[0]);  // read only where the exponent varies
     }},
    {"sin", 1, [](const double* a) { return std::sin(a[0]); },
     [](const double* a, double* d) { d[0] = std::cos(a[0]); }},
    {"cos", 1, [](const double* a) { return std::cos(a[0]); },
     [](const double* a, double* d) { d[0] = -std::sin(a[0]); }},
    {"tan", 1, [](const double* a) { return std::tan(a[0]); },
     [](const double* a, double* d) { d[0] = 1.0 + std::tan(a[0]) * std::tan(a[0]); }},
    {"asin", 1, [](const double* a) { return std::asin(a[0]); },
     [](const double* a, double* d) { d[0] = 1.0 / std::sqrt(1.0 - a[0] * a[0]); }},
    {"acos", 1, [](const double* a) { return std::acos(a[0]); },
     [](const double* a, double* d) { d[0] = -1.0 / std::sqrt(1.0 - a[0] * a[0]); }},
    {"atan", 1, [](const double* a) { return std::atan(a[0]); },
     [](const double* a, double* d) { d[0] = 1.0 / (1.0 + a[0] * a[0]); }},
    {"atan2", 2, [](const double* a) { return std::atan2(a[0], a[1]); },
     [](const double* a, double* d) {
       const double r2 = a[0] * a[0] + a[1] * a[1];
       d[0] = a[1] / r2;
       d[1] = -a[0] / r2;
     }},
    {"sqrt", 1, [](const double* a) { return std::sqrt(a[0]); },
     [](const double* a, double* d) { d[0] = 0.5 / std::sqrt(a[0]); }},
    {"exp", 1, [](const double* a) { return std::exp(a[0]); },
     [](const double* a, double* d) { d[0] = std::exp(a[0]); }},
    {"log", 1, [](const double* a) { return std::log(a[0]); },
     [](const double* a, double* d) { d[0] = 1.0 / a[0]; }},
    // From x = 0 on, the right-hand derivative.
    {"abs", 1, [](const double* a) { return std::abs(a[0]); },
     [](const double* a, double* d) { d[0] = a[0] < 0.0 ? -1.0 : 1.0; }},
    {"sign", 1, [](const double* a) { return a[0] > 0.0   ? 1.0
                                             : a[0] < 0.0 ? -1.0
                                                          : 0.0; },
     [](const double*, double* d) { d[0] = 0.0; }},
    // Heaviside: 1 from x = 0 on.
    {"step", 1, [](const double* a) { return a[0] >= 0.0 ? 1.0 : 0.0; },
     [](const double*, double* d) { d[0] = 0.0; }},
    // std::min gives a[0] unless a[1] < a[0], std::max unless a[0] < a[1].
    {"min", 2, [](const double* a) { return std::min(a[0], a[1]); },
     [](const double* a, double* d) {
       d[0] = a[1] < a[0] ? 0.0 : 1.0;
       d[1] = 1.0 - d[0];
     }},
    {"max", 2, [](const double* a) { return std::max(a[0], a[1]); },
     [](const double* a, double* d) {
       d[0] = a[0] < a[1] ? 0.0 : 1.0;
       d[1] = 1.0 - d[0];
     }},
    // clamp(x, lo, hi) = max(lo, min(x, hi)): the derivative of the argument it returns.
    {"clamp", 3, [](const double* a) { return std::max(a[1], std::min(a[0], a[2])); },
     [](const double* a, double* d) {
       const bool upper = a[2] < a[0], lower = !(a[1] < (upper ? a[2] : a[0]));
       d[0] = !lower && !upper ? 1.0 : 0.0;
       d[1] = lower ? 1.0 : 0.0;
       d[2] = !lower && upper ? 1.0 : 0.0;
     }},
};

static_assert(std::ranges::all_of(kFunctions,
                                  [](const Function& f) { return f.arity <= kMaxArity; }));

const Function& function(std::string_view name) {
  for (const auto& f : kFunctions) {
    if (name == f.name) return f;
  }
  throw std::logic_error("expression: no operator " + std::string(name));
}

const Function* find_function(std::string_view name) {
  for (const auto& f : kFunctions) {
    if (name == f.name && std::isalpha(static_cast<unsigned char>(f.name[0]))) return &f;
  }
  return nullptr;
}

std::string function_names() {
  std::vector<std::string> names;
  for (const auto& f : kFunctions) {
    if (std::isalpha(static_cast<unsigned char>(f.name[0])) && std::string_view(f.name) != "neg") {
      names.push_back(f.name);
    }
  }
  return fmt::format("{}", fmt::join(names, ", "));
}

bool name_start(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
}

// Recursive descent straight into the stack program. Nesting is bounded so
// that a hostile text cannot exhaust the stack.
class Parser {
 public:
  Parser(std::string_view text, const Resolver& resolver) : text_(text), resolver_(resolver) {}

  std::vector<Expression::Op> parse() {
    expression();
    skip_space();
    if (pos_ < text_.size()) fail(fmt::format("unexpected '{}'", text_[pos_]));
    return std::move(ops_);
  }

 private:
  static constexpr int kMaxDepth = 100;

  [[noreturn]] void fail(const std::string& what) const {
    throw ExpressionError(fmt::format("in '{}' at column {}: {}", text_, pos_ + 1, what));
  }

  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c))
      fail(pos_ < text_.size() ? fmt::format("expected '{}', found '{}'", c, text_[pos_])
                               : fmt::format("expected '{}' at the end", c));
  }
  void emit(const Function& f) {
    ops_.push_back({.kind = Expression::Op::Kind::function,
                    .function = f.value,
                    .partials = f.partials,
                    .arity = f.arity});
  }

  void expression() {
    if (++depth_ > kMaxDepth) fail(fmt::format("nested more than {} deep", kMaxDepth));
    term();
    for (;;) {
      if (accept('+')) {
        term();
        emit(function("+"));
      } else if (accept('-')) {
        term();
        emit(function("-"));
      } else {
        break;
      }
    }
    --depth_;
  }
  void term() {
    unary();
    for (;;) {
      if (accept('*')) {
        unary();
        emit(function("*"));
      } else if (accept('/')) {
        unary();
        emit(function("/"));
      } else {
        break;
      }
    }
  }
  void unary() {
    if (++depth_ > kMaxDepth) fail(fmt::format("nested more than {} deep", kMaxDepth));
    if (accept('-')) {
      unary();
      emit(function("neg"));
    } else {
      primary();
      if (accept('^')) {
        unary();
        emit(function("^"));
      }
    }
    --depth_;
  }
  void primary() {
    skip_space();
    if (pos_ >= text_.size()) fail("expected a number, a name or '(' at the end");
    const char c = text_[pos_];
    if (accept('(')) {
      expression();
      expect(')');
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      number();
    } else if (name_start(c)) {
      name();
    } else {
      fail(fmt::format("expected a number, a name or '(', found '{}'", c));
    }
  }
  void number() {
    const char* begin = text_.data() + pos_;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(begin, text_.data() + text_.size(), v);
    if (ec != std::errc() || !std::isfinite(v)) fail("not a finite number");
    pos_ += static_cast<std::size_t>(end - begin);
    ops_.push_back({.kind = Expression::Op::Kind::number, .number = v});
  }
  void name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && name_char(text_[pos_])) ++pos_;
    const std::string_view id = text_.substr(start, pos_ - start);
    if (accept('(')) {
      call(id, start);
    } else if (id == "pi") {
      ops_.push_back({.kind = Expression::Op::Kind::number, .number = std::numbers::pi});
    } else {
      if (!resolver_.symbol) fail(fmt::format("unknown name '{}'", id));
      push_symbol(resolved([&] { return resolver_.symbol(id); }, start), start, id);
    }
  }
  // What the resolver says, its refusal with the column of the name.
  template <class F>
  int resolved(F&& resolve, std::size_t start) {
    try {
      return resolve();
    } catch (const ExpressionError& e) {
      pos_ = start;
      fail(e.what());
    }
  }
  void push_symbol(int symbol, std::size_t, std::string_view) {
    ops_.push_back({.kind = Expression::Op::Kind::symbol, .symbol = symbol});
  }
  // The argument texts of a call, split at the top-level commas.
  std::vector<std::string_view> argument_texts() {
    std::vector<std::string_view> args;
    int level = 0;
    std::size_t start = pos_;
    for (; pos_ < text_.size(); ++pos_) {
      const char c = text_[pos_];
      if (c == '(') ++level;
      if (c == ')' && level-- == 0) break;
      if (c == ',' && level == 0) {
        args.push_back(text_.substr(start, pos_ - start));
        start = pos_ + 1;
      }
    }
    if (pos_ >= text_.size()) fail("expected ')' at the end");
    args.push_back(text_.substr(start, pos_ - start));
    ++pos_;
    return args;
  }
  void call(std::string_view id, std::size_t start) {
    if (const Function* f = find_function(id)) {
      int n = 0;
      if (!accept(')')) {
        do {
          expression();
          ++n;
        } while (accept(','));
        expect(')');
      }
      if (n != f->arity) {
        pos_ = start;
        fail(fmt::format("{}() takes {} argument{}, given {}", id, f->arity,
                         f->arity == 1 ? "" : "s", n));
      }
      emit(*f);
      return;
    }
    const std::size_t open = pos_;
    const auto args = argument_texts();
    const int symbol =
        resolver_.call ? resolved([&] { return resolver_.call(id, args); }, start) : -1;
    if (symbol < 0) {
      pos_ = open;
      fail(fmt::format("unknown function '{}' (functions: {})", id, function_names()));
    }
    push_symbol(symbol, start, id);
  }

  std::string_view text_;
  const Resolver& resolver_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  std::vector<Expression::Op> ops_;
};

// The deepest the stack gets while the program runs.
std::size_t stack_depth(const std::vector<Expression::Op>& ops) {
  std::size_t depth = 0, deepest = 0;
  for (const auto& op : ops) {
    depth = op.kind == Expression::Op::Kind::function
                ? depth - static_cast<std::size_t>(op.arity) + 1
                : depth + 1;
    deepest = std::max(deepest, depth);
  }
  return deepest;
}

}  // namespace

Expression Expression::parse(std::string_view text, const Resolver& resolver) {
  Expression e;
  e.text_ = std::string(text);
  e.ops_ = Parser(e.text_, resolver).parse();
  for (const auto& op : e.ops_) {
    if (op.kind == Op::Kind::symbol &&
        std::find(e.symbols_.begin(), e.symbols_.end(), op.symbol) == e.symbols_.end()) {
      e.symbols_.push_back(op.symbol);
    }
  }
  e.stack_ = std::make_shared<std::vector<double>>(stack_depth(e.ops_));
  for (auto& op : e.ops_) {
    if (op.kind != Op::Kind::symbol) continue;
    op.slot = static_cast<int>(std::find(e.symbols_.begin(), e.symbols_.end(), op.symbol) -
                               e.symbols_.begin());
  }
  e.gradients_ = std::make_shared<Gradients>(
      Gradients{std::vector<double>(e.stack_->size() * e.symbols_.size()),
                std::vector<char>(e.stack_->size())});
  return e;
}

Expression Expression::constant(double value) {
  Expression e;
  e.text_ = fmt::format("{}", value);
  e.ops_.push_back({.kind = Op::Kind::number, .number = value});
  e.stack_ = std::make_shared<std::vector<double>>(1);
  e.gradients_ = std::make_shared<Gradients>(Gradients{{}, std::vector<char>(1)});
  return e;
}

double Expression::evaluate(const Environment& env) const {
  if (ops_.empty()) return 0.0;
  double* stack = stack_->data();
  std::size_t top = 0;
  for (const auto& op : ops_) {
    switch (op.kind) {
      case Op::Kind::number:
        stack[top++] = op.number;
        break;
      case Op::Kind::symbol:
        stack[top++] = env.value(op.symbol);
        break;
      case Op::Kind::function: {
        top -= static_cast<std::size_t>(op.arity);
        stack[top] = op.function(stack + top);
        ++top;
        break;
      }
    }
  }
  return stack[0];
}

// Forward mode: each entry of the stack carries its gradient with respect to
// the symbols (row `top` of g) and whether it varies at all, so that a
// constant argument's partial derivative, possibly not finite (the exponent's
// log of a negative base), is never read. A partial derivative multiplies only
// the gradient's non-zero entries: sqrt(vx^2 + vy^2) at rest has a gradient of
// 0, not 0·∞.
double Expression::evaluate(const Environment& env, double* gradient) const {
  const std::size_t n = symbols_.size();
  if (ops_.empty()) {
    std::fill(gradient, gradient + n, 0.0);
    return 0.0;
  }
  double* stack = stack_->data();
  double* g = gradients_->rows.data();
  char* varies = gradients_->varies.data();
  double partials[kMaxArity];
  std::size_t top = 0;
  for (const auto& op : ops_) {
    switch (op.kind) {
      case Op::Kind::number:
        varies[top] = 0;
        stack[top++] = op.number;
        break;
      case Op::Kind::symbol:
        std::fill(g + top * n, g + (top + 1) * n, 0.0);
        g[top * n + static_cast<std::size_t>(op.slot)] = 1.0;
        varies[top] = 1;
        stack[top++] = env.value(op.symbol);
        break;
      case Op::Kind::function: {
        top -= static_cast<std::size_t>(op.arity);
        op.partials(stack + top, partials);
        // The result overwrites the first argument: its own term first.
        double* out = g + top * n;
        bool any = varies[top] != 0;
        if (any) {
          for (std::size_t c = 0; c < n; ++c) out[c] = out[c] != 0.0 ? out[c] * partials[0] : 0.0;
        }
        for (int i = 1; i < op.arity; ++i) {
          const std::size_t slot = top + static_cast<std::size_t>(i);
          if (!varies[slot]) continue;
          if (!any) std::fill(out, out + n, 0.0);
          any = true;
          for (std::size_t c = 0; c < n; ++c) {
            if (g[slot * n + c] != 0.0) out[c] += partials[i] * g[slot * n + c];
          }
        }
        varies[top] = any ? 1 : 0;
        stack[top] = op.function(stack + top);
        ++top;
        break;
      }
    }
  }
  if (varies[0]) {
    std::copy(g, g + n, gradient);
  } else {
    std::fill(gradient, gradient + n, 0.0);
  }
  return stack[0];
}

}  // namespace symdyn::sim
