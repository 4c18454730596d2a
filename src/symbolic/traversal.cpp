#include <algorithm>
#include <unordered_set>

#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::symbolic {

// Iterative, so that deep DAGs cannot overflow the stack.
std::vector<Expr> postorder(std::span<const Expr> roots) {
  std::vector<Expr> order;
  std::unordered_set<std::uint32_t> seen;
  std::vector<std::pair<Expr, std::size_t>> stack;  // node, next child to visit
  for (Expr root : roots) {
    if (!seen.insert(root.id()).second) continue;
    stack.emplace_back(root, 0);
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < node.args().size()) {
        const Expr child = node.arg(next++);
        if (seen.insert(child.id()).second) stack.emplace_back(child, 0);
      } else {
        order.push_back(node);
        stack.pop_back();
      }
    }
  }
  return order;
}

std::size_t dag_size(std::span<const Expr> roots) {
  return postorder(roots).size();
}

std::vector<Expr> free_symbols(std::span<const Expr> roots) {
  std::vector<Expr> symbols;
  for (Expr e : postorder(roots)) {
    if (e.is_symbol()) symbols.push_back(e);
  }
  std::sort(symbols.begin(), symbols.end(),
            [](Expr a, Expr b) { return a.symbol_index() < b.symbol_index(); });
  return symbols;
}

bool depends_on(Expr e, Expr symbol) {
  const auto symbols = free_symbols(std::span<const Expr>(&e, 1));
  return std::find(symbols.begin(), symbols.end(), symbol) != symbols.end();
}

}  // namespace symdyn::symbolic
