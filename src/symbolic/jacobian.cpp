#include <fmt/format.h>

#include <unordered_map>

#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/jacobian.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::symbolic {
namespace {

// Which definitions the outputs read, directly or through other definitions.
std::vector<bool> reached_definitions(std::span<const Expr> outputs,
                                      std::span<const Definition> definitions,
                                      const std::unordered_map<Expr, std::size_t>& index_of) {
  std::vector<bool> reached(definitions.size(), false);
  std::vector<std::size_t> pending;
  const auto reach = [&](std::span<const Expr> roots) {
    for (Expr s : free_symbols(roots)) {
      const auto it = index_of.find(s);
      if (it != index_of.end() && !reached[it->second]) {
        reached[it->second] = true;
        pending.push_back(it->second);
      }
    }
  };
  reach(outputs);
  while (!pending.empty()) {
    const std::size_t d = pending.back();
    pending.pop_back();
    reach(std::span<const Expr>(&definitions[d].value, 1));
  }
  return reached;
}

}  // namespace

ChainJacobian chain_jacobian(std::span<const Expr> outputs, std::span<const Expr> variables,
                             std::span<const Definition> definitions) {
  std::unordered_map<Expr, std::size_t> index_of;
  for (std::size_t d = 0; d < definitions.size(); ++d) index_of.emplace(definitions[d].symbol, d);
  for (Expr x : variables) {
    if (!x.is_symbol())
      throw UsageError(fmt::format("chain_jacobian: the variable '{}' is not a symbol", x.str()));
    if (index_of.contains(x))
      throw UsageError(fmt::format("chain_jacobian: the variable '{}' is defined", x.name()));
  }
  const std::vector<bool> reached = reached_definitions(outputs, definitions, index_of);
  ChainJacobian out;
  out.entries.resize(outputs.size() * variables.size());
  for (std::size_t j = 0; j < variables.size(); ++j) {
    const Expr x = variables[j];
    DirectionalDerivative d_dx(std::unordered_map<Expr, Expr>{{x, Expr(1)}});
    for (std::size_t k = 0; k < definitions.size(); ++k) {
      if (!reached[k]) continue;
      const Definition& def = definitions[k];
      const Expr derivative = d_dx(def.value);
      if (derivative.is_zero()) continue;
      if (derivative.is_number() || derivative.is_symbol()) {
        d_dx.add(def.symbol, derivative);
        continue;
      }
      const Expr named =
          symbol(fmt::format("d({})/d({})", def.symbol.name(), x.name()), SymbolKind::Intermediate);
      out.definitions.push_back({named, derivative});
      d_dx.add(def.symbol, named);
    }
    for (std::size_t i = 0; i < outputs.size(); ++i)
      out.entries[i * variables.size() + j] = d_dx(outputs[i]);
  }
  return out;
}

}  // namespace symdyn::symbolic
