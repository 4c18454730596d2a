#pragma once
// Rule tables of the simplifier (rows of rewrite.hpp rules), built in the
// current context. Wildcards: a, b are cofactors (_a, _b), x, y match one
// expression (_x, _y), R is the rest of a sum (_R).
//
// Adding a rule is adding a row to one of the tables in trig_rules.cpp; the
// rule fuzz test (tests/symbolic/simplify_test.cpp) checks every row.

#include <string_view>
#include <vector>

#include <symdyn/symbolic/rewrite.hpp>

namespace symdyn::symbolic {

// Identities that remove calls or terms; used with Strategy::Improve, so each
// fires only where it lowers the cost:
//   a sin²x + a cos²x = a, a sin²x + b cos²x = a + (b - a) cos²x, a - a sin²x = a cos²x,
//   a cos x cos y ∓ a sin x sin y = a cos(x ± y), a sin x cos y ± a cos x sin y = a sin(x ± y),
//   a sin x cos x = a/2 sin 2x, a cos²x - a sin²x = a cos 2x, ...
std::vector<Rule> contracting_trig_rules();

// sin(x + R) and cos(x + R) expanded by the angle-sum formulas, sin 2x and
// cos 2x by the double-angle ones (Normalize).
std::vector<Rule> expanding_trig_rules();

// Products of sines and cosines to sums of sines and cosines of sums of the
// angles, like Giac's tlin (Normalize; alternate with expand to linearize fully).
std::vector<Rule> linearizing_trig_rules();

// sin²x -> 1 - cos²x (and odd powers: sin³x -> sin x (1 - cos²x)) (Normalize).
// After expand, a polynomial in sines and cosines reaches a normal form modulo
// sin² + cos² = 1: two forms equal by that identity become the same node.
std::vector<Rule> sin_squared_elimination();
// The same with the roles of sin and cos exchanged.
std::vector<Rule> cos_squared_elimination();

// Algebraic clean-ups with sound conditions (Improve): sqrt(x²) = |x|,
// |x| = x for x known to be >= 0. (sin, cos and tan of asin, acos and atan
// are reduced by construction: expr.hpp.)
std::vector<Rule> algebraic_rules();

// Every table above by name, for tests and tools.
struct RuleTable {
  std::string_view name;
  std::vector<Rule> rules;
};
std::vector<RuleTable> all_rule_tables();

}  // namespace symdyn::symbolic
