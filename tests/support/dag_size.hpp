#pragma once
// The number of distinct nodes reachable from a set of outputs (each node of
// the DAG counted once, whatever sharing it has), iteratively.

#include <span>
#include <unordered_set>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::testing {

inline std::size_t count_dag_nodes(std::span<const symbolic::Expr> outputs) {
  std::unordered_set<const symbolic::Node*> seen;
  std::vector<symbolic::Expr> stack(outputs.begin(), outputs.end());
  while (!stack.empty()) {
    const symbolic::Expr e = stack.back();
    stack.pop_back();
    if (!seen.insert(e.node()).second) continue;
    for (symbolic::Expr a : e.args()) stack.push_back(a);
  }
  return seen.size();
}

}  // namespace symdyn::testing
