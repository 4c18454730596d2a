// Random builder calls, most of them wrong (bad names, non-finite numbers,
// undeclared symbols, unknown references, expressions out of their domain),
// then validate() and, on small valid models, generate() with random options:
// each call either succeeds or throws model::ModelError, nothing else, and
// never crashes (the debug preset runs this under ASan and UBSan).
#include <rapidcheck/catch.h>

#include <cmath>
#include <limits>
#include <typeinfo>

#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/model.hpp>

using namespace symdyn;
using model::Expr;

namespace {

const std::vector<std::string> kNames = {"q0", "q1",    "q2",  "t",     "b0",   "b1",  "b2",
                                         "p0", "alpha", "l1",  "class", "2x",   "a-b", "",
                                         "_X", "x__y",  "rod", "int",   "q0_d", "qd0"};
const std::vector<double> kNumbers = {0.0,
                                      1.0,
                                      -1.0,
                                      0.5,
                                      2.0,
                                      1e-300,
                                      1e308,
                                      std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity()};

// Any other exception type, caught and described, fails the property.
template <class F>
bool only_model_errors(const char* what, F&& call) {
  try {
    call();
    return true;
  } catch (const model::ModelError&) {
    return false;
  } catch (const std::exception& e) {
    RC_FAIL(fmt::format("{} threw {}: {}", what, typeid(e).name(), e.what()));
  }
  return false;
}

// Seven choices in eight are right, so that models often get through
// validate() and on to generate(); the eighth is wrong in some way.
bool right() {
  return *rc::gen::inRange(0, 8) > 0;
}

class RandomCalls {
 public:
  void run() {
    const std::string name =
        right() ? "fuzz" : *rc::gen::elementOf(std::vector<std::string>{"2bad", "", "a b"});
    if (!only_model_errors("Model()", [&] { model_.emplace(name); })) return;
    // Symbols are the process's, across models: an earlier case's coordinate
    // "qd0" makes q0's rate a model error here too.
    if (right() && !only_model_errors("pendulum", [&] { pendulum(); })) return;
    const int calls = *rc::gen::inRange(0, 6);
    for (int i = 0; i < calls; ++i) call();
    if (!only_model_errors("validate", [&] { model_->validate(); })) return;
    RC_TAG("valid");
    if (model_->bodies().size() > 3 || model_->coordinates().size() > 3) return;
    if (only_model_errors("generate",
                          [&] { codegen::generate(*model_, variant(), basename(), options()); })) {
      RC_TAG("generated");
    }
  }

 private:
  // A valid one-body pendulum to build on.
  void pendulum() {
    const Expr q = model_->coordinate(fmt::format("q{}", fresh_++));
    symbols_.push_back(q);
    model_->body(fmt::format("body{}", fresh_++))
        .mass(1.0)
        .inertia(0.1, 0.2, 0.25)
        .motion(model::Trotz(q) * model::Tdisp(1, 0, 0));
  }

  std::string name() {
    return right() ? fmt::format("n{}", fresh_++) : *rc::gen::elementOf(kNames);
  }
  double number() {
    return right() ? *rc::gen::elementOf(std::vector<double>{0.3, 1.0, 2.0})
                   : *rc::gen::elementOf(kNumbers);
  }

  // A declared symbol, a stray one, or a number.
  Expr leaf() {
    switch (*rc::gen::inRange(0, 5)) {
      case 0:
      case 4:
        return symbols_.empty() ? Expr(1) : *rc::gen::elementOf(symbols_);
      case 1:
        return symbolic::symbol(fmt::format("stray{}", *rc::gen::inRange(0, 3)),
                                symbolic::SymbolKind::Variable);
      case 2:
        return model_->time();
      default:
        return Expr(*rc::gen::inRange(-3, 4) * 0.5);
    }
  }

  // An expression the symbolic engine accepts, or nothing: its own errors
  // (asin(2), 1/0) are thrown where the expression is made, before any builder call.
  std::optional<Expr> expression(int depth = 2) {
    try {
      if (depth == 0) return leaf();
      const auto a = expression(depth - 1), b = expression(depth - 1);
      if (!a || !b) return std::nullopt;
      switch (*rc::gen::inRange(0, 8)) {
        case 0:
          return *a + *b;
        case 1:
          return *a * *b;
        case 2:
          return *a / *b;
        case 3:
          return sin(*a);
        case 4:
          return asin(*a);
        case 5:
          return sqrt(*a);
        case 6:
          return log(*a);
        default:
          return *a;
      }
    } catch (const symbolic::SymbolicError&) {
      return std::nullopt;
    }
  }

  void call() {
    model::Model& m = *model_;
    switch (*rc::gen::inRange(0, 8)) {
      case 0:
        only_model_errors("coordinate", [&] { symbols_.push_back(m.coordinate(name())); });
        break;
      case 1:
        only_model_errors("parameter", [&] {
          symbols_.push_back(m.parameter(name(), number(), *rc::gen::arbitrary<bool>()));
        });
        break;
      case 2:
        if (const auto e = expression())
          only_model_errors("dependent", [&] { symbols_.push_back(m.dependent(name(), *e)); });
        break;
      case 3:
        if (const auto g = expression(0))
          only_model_errors("gravity", [&] { m.gravity(number(), *g, -9.81); });
        break;
      case 4:
        only_model_errors("initial", [&] { m.initial(leaf(), number(), number()); });
        break;
      case 5:
        m.inline_dependents(*rc::gen::arbitrary<bool>());
        break;
      default:
        body();
    }
  }

  void body() {
    const auto angle = expression(1), offset = expression(1), mass = expression(0);
    if (!angle || !offset || !mass) return;
    only_model_errors("body", [&] {
      model::Body& b = model_->body(name());
      if (right())
        b.mass(number());
      else
        b.mass(*mass);
      // Equal moments satisfy every inequality: a right body stays right.
      const double moment = number();
      if (right()) {
        b.inertia(moment, moment, moment);
      } else {
        b.inertia(number(), number(),
                  *rc::gen::arbitrary<bool>() ? model::Scalar(number()) : model::Scalar(*mass));
      }
      if (*rc::gen::inRange(0, 5) > 0) b.motion(model::Trotz(*angle) * model::Tdisp(*offset, 0, 0));
      if (*rc::gen::inRange(0, 3) == 0)
        b.relative_to(right() ? model_->bodies().front().name() : name());
    });
  }

  std::string variant() {
    return right() ? "default" : *rc::gen::elementOf(std::vector<std::string>{"inline", "a b", ""});
  }
  std::string basename() {
    return right() ? "fuzz_a" : *rc::gen::elementOf(std::vector<std::string>{"class", "f-b", "_F"});
  }
  codegen::Options options() {
    codegen::Options o;
    o.simplify = *rc::gen::arbitrary<bool>();
    o.symbolic_partials = *rc::gen::arbitrary<bool>();
    o.equations_of_motion = *rc::gen::arbitrary<bool>();
    o.part_instructions = *rc::gen::elementOf(std::vector<std::size_t>{0, 1, 8, 125});
    o.split_above = *rc::gen::elementOf(std::vector<std::size_t>{0, 500});
    o.name_space = right()
                       ? "symdyn_generated"
                       : *rc::gen::elementOf(std::vector<std::string>{"a::b", "a::", "int", ""});
    return o;
  }

  std::optional<model::Model> model_;
  std::vector<Expr> symbols_;
  int fresh_ = 0;
};

}  // namespace

TEST_CASE("random builder calls end in success or model::ModelError only", "[fuzz]") {
  rc::prop("builder, validate and generate", [] { RandomCalls().run(); });
}
