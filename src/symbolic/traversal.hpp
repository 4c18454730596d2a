#pragma once
// Walking the DAG: every node reachable from a set of roots, each once.

#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

// Every node reachable from the roots, each once, children before parents.
// Deterministic: depends only on the roots and their structure.
std::vector<Expr> postorder(std::span<const Expr> roots);

// Number of distinct nodes reachable from the roots.
std::size_t dag_size(std::span<const Expr> roots);

// The symbols the roots depend on, in declaration order.
std::vector<Expr> free_symbols(std::span<const Expr> roots);

// True if e depends on the symbol.
bool depends_on(Expr e, Expr symbol);

}  // namespace symdyn::symbolic
