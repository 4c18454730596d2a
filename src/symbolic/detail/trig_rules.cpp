// The rule tables. One row per identity; see trig_rules.hpp for how each
// table is used.
#include <symdyn/symbolic/detail/trig_rules.hpp>

namespace symdyn::symbolic {
namespace {

struct Wild {
  Expr a = wildcard("_a");
  Expr b = wildcard("_b");
  Expr x = wildcard("_x");
  Expr y = wildcard("_y");
  Expr R = wildcard("_R");
};

Expr sq(Expr e) {
  return pow(e, 2);
}

}  // namespace

std::vector<Rule> contracting_trig_rules() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {
      rule("sin2+cos2", a * sq(sin(x)) + a * sq(cos(x)), a),
      rule("a*sin2+b*cos2->cos2", a * sq(sin(x)) + b * sq(cos(x)), a + (b - a) * sq(cos(x))),
      rule("a*sin2+b*cos2->sin2", a * sq(sin(x)) + b * sq(cos(x)), b + (a - b) * sq(sin(x))),
      rule("1-sin2", a - a * sq(sin(x)), a * sq(cos(x))),
      rule("1-cos2", a - a * sq(cos(x)), a * sq(sin(x))),
      rule("cos(x+y)", a * cos(x) * cos(y) - a * sin(x) * sin(y), a * cos(x + y)),
      rule("cos(x-y)", a * cos(x) * cos(y) + a * sin(x) * sin(y), a * cos(x - y)),
      rule("sin(x+y)", a * sin(x) * cos(y) + a * cos(x) * sin(y), a * sin(x + y)),
      rule("sin(x-y)", a * sin(x) * cos(y) - a * cos(x) * sin(y), a * sin(x - y)),
      rule("cos2-sin2", a * sq(cos(x)) - a * sq(sin(x)), a * cos(2 * x)),
      rule("2cos2-1", 2 * a * sq(cos(x)) - a, a * cos(2 * x)),
      rule("1-2sin2", a - 2 * a * sq(sin(x)), a * cos(2 * x)),
      rule("2sin*cos", a * sin(x) * cos(x), a / 2 * sin(2 * x)),
  };
}

std::vector<Rule> expanding_trig_rules() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {
      rule("expand sin(x+R)", sin(x + R), sin(x) * cos(R) + cos(x) * sin(R)),
      rule("expand cos(x+R)", cos(x + R), cos(x) * cos(R) - sin(x) * sin(R)),
      rule("expand sin(2a)", sin(2 * a), 2 * sin(a) * cos(a), integer_coefficient("_a")),
      rule("expand cos(2a)", cos(2 * a), sq(cos(a)) - sq(sin(a)), integer_coefficient("_a")),
  };
}

std::vector<Rule> linearizing_trig_rules() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {
      rule("tlin sin2", a * sq(sin(x)), a * (1 - cos(2 * x)) / 2),
      rule("tlin cos2", a * sq(cos(x)), a * (1 + cos(2 * x)) / 2),
      rule("tlin sin*sin", a * sin(x) * sin(y), a * (cos(x - y) - cos(x + y)) / 2),
      rule("tlin cos*cos", a * cos(x) * cos(y), a * (cos(x - y) + cos(x + y)) / 2),
      rule("tlin sin*cos", a * sin(x) * cos(y), a * (sin(x + y) + sin(x - y)) / 2),
  };
}

std::vector<Rule> sin_squared_elimination() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {rule("sin2->1-cos2", a * sq(sin(x)), a * (1 - sq(cos(x))))};
}

std::vector<Rule> cos_squared_elimination() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {rule("cos2->1-sin2", a * sq(cos(x)), a * (1 - sq(sin(x))))};
}

std::vector<Rule> algebraic_rules() {
  [[maybe_unused]] const auto [a, b, x, y, R] = Wild{};
  return {
      rule("sqrt(x^2)", sqrt(sq(x)), abs(x)),
      rule("abs of nonnegative", abs(x), x, nonnegative("_x")),
  };
}

std::vector<RuleTable> all_rule_tables() {
  return {
      {"contracting trig", contracting_trig_rules()},
      {"expanding trig", expanding_trig_rules()},
      {"linearizing trig", linearizing_trig_rules()},
      {"sin2 elimination", sin_squared_elimination()},
      {"cos2 elimination", cos_squared_elimination()},
      {"algebraic", algebraic_rules()},
  };
}

}  // namespace symdyn::symbolic
