#pragma once
// symdyn::symbolic, the engine: expressions, derivatives, simplification,
// straight-line programs, printing and evaluation (docs/design.md).

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/dag_map.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/eval.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/jacobian.hpp>
#include <symdyn/symbolic/node_kinds.hpp>
#include <symdyn/symbolic/node_table.hpp>
#include <symdyn/symbolic/number.hpp>
#include <symdyn/symbolic/print.hpp>
#include <symdyn/symbolic/program.hpp>
#include <symdyn/symbolic/rewrite.hpp>
#include <symdyn/symbolic/scalar_ops.hpp>
#include <symdyn/symbolic/simplify.hpp>
#include <symdyn/symbolic/traversal.hpp>
#include <symdyn/symbolic/trig_polynomial.hpp>
