#pragma once
// Printing expressions.
//
// Readable infix with minimal parentheses: "2*x + sin(q0)^2 - y/(a + b)".
// Sums print their negative terms with "-", products their negative powers as
// a denominator, x^(1/2) as sqrt(x).
//
// C++: the same expression as a C++ expression over doubles, for the emitter and
// for debugging ("std::sin(q0)*std::sin(q0)" for sin(q0)^2, constants as
// round-trip double literals "0.5", "9.81", "2.0"). Symbols print under their
// name, or through `name_of` when given.

#include <functional>
#include <string>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

std::string to_infix(Expr e);

using SymbolNamer = std::function<std::string(Expr symbol)>;
std::string to_cpp(Expr e, const SymbolNamer& name_of = {});

// A double as a C++ literal that reads back to the same value ("2.0", "0.1", "1e-09").
std::string cpp_literal(double value);

}  // namespace symdyn::symbolic
