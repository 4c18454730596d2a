// Differentiation, total time derivative and substitution: three DagMap rules.
// The calculus is in one place, the table of local partials below.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include <symdyn/symbolic/diff.hpp>

namespace symdyn::symbolic {
namespace {

// ---------------------------------------------------------------------------
// The table of local partials: one row per compound kind. A row computes
// ∂node/∂arg_i from the node and its arguments; rows are asked only for the
// arguments whose own derivative is not zero.

using Partial = Expr (*)(Expr node, std::size_t i);
struct PartialRow {
  Kind kind;
  Partial partial;
};

// prod_{j != i} f_j: the partial of a product with respect to its factor f_i.
Expr product_of_others(Expr product, std::size_t i) {
  std::vector<Expr> others;
  others.reserve(product.args().size() - 1);
  for (std::size_t j = 0; j < product.args().size(); ++j) {
    if (j != i) others.push_back(product.arg(j));
  }
  return mul(others);
}

Expr power_partial(Expr power, std::size_t i) {
  if (i != 0)
    throw UsageError(fmt::format("partial: the exponent of '{}' is a constant", power.str()));
  const Number& e = power.arg(1).number();
  return Expr(e) * pow(power.arg(0), Expr(e - Number(1)));
}

Expr atan2_partial(Expr node, std::size_t i) {
  const Expr y = node.arg(0);
  const Expr x = node.arg(1);
  const Expr inverse_norm2 = pow(pow(x, 2) + pow(y, 2), -1);
  return i == 0 ? x * inverse_norm2 : -y * inverse_norm2;
}

// 1/sqrt(1 - x²)
Expr inverse_cosine_of_asin(Expr x) {
  return pow(1 - pow(x, 2), rational(-1, 2));
}

constexpr PartialRow kPartials[] = {
    {Kind::Add, [](Expr, std::size_t) { return Expr(1); }},
    {Kind::Mul, product_of_others},
    {Kind::Pow, power_partial},
    {Kind::Sin, [](Expr e, std::size_t) { return cos(e.arg(0)); }},
    {Kind::Cos, [](Expr e, std::size_t) { return -sin(e.arg(0)); }},
    {Kind::Tan, [](Expr e, std::size_t) { return 1 + pow(e, 2); }},
    {Kind::Asin, [](Expr e, std::size_t) { return inverse_cosine_of_asin(e.arg(0)); }},
    {Kind::Acos, [](Expr e, std::size_t) { return -inverse_cosine_of_asin(e.arg(0)); }},
    {Kind::Atan, [](Expr e, std::size_t) { return pow(1 + pow(e.arg(0), 2), -1); }},
    {Kind::Atan2, atan2_partial},
    {Kind::Exp, [](Expr e, std::size_t) { return e; }},
    {Kind::Log, [](Expr e, std::size_t) { return pow(e.arg(0), -1); }},
    {Kind::Abs, [](Expr e, std::size_t) { return e.arg(0) * pow(e, -1); }},
};

#define SYMDYN_KIND_ARITY(kind, name, arity, cpp, cost) arity,
constexpr int kArity[] = {SYMDYN_FOR_EACH_KIND(SYMDYN_KIND_ARITY)};
#undef SYMDYN_KIND_ARITY
constexpr std::size_t kKindCount = std::size(kArity);

constexpr std::array<Partial, kKindCount> kPartialByKind = [] {
  std::array<Partial, kKindCount> table{};
  for (const PartialRow& row : kPartials) table[static_cast<std::size_t>(row.kind)] = row.partial;
  return table;
}();

// Adding a compound kind to node_kinds.hpp without its row is a compile error.
static_assert([] {
  for (std::size_t k = 0; k < kKindCount; ++k) {
    if ((kArity[k] != 0) != (kPartialByKind[k] != nullptr)) return false;
  }
  return true;
}());

// ---------------------------------------------------------------------------
// The chain rule over the table: d node = sum_i ∂node/∂a_i · d a_i.

Expr chain_rule(Expr node, std::span<const Expr> arg_derivatives) {
  std::vector<Expr> terms;
  for (std::size_t i = 0; i < arg_derivatives.size(); ++i) {
    const Expr d = arg_derivatives[i];
    if (d.is_zero()) continue;
    if (node.kind() == Kind::Add) {
      terms.push_back(d);
    } else if (node.kind() == Kind::Mul) {
      // (prod_{j != i} f_j)·d f_i in one product: no intermediate node for
      // the product of the others.
      std::vector<Expr> factors(node.args().begin(), node.args().end());
      factors[i] = d;
      terms.push_back(mul(factors));
    } else {
      terms.push_back(partial(node, i) * d);
    }
  }
  return add(terms);
}

// A DagMap rule for a derivative: leaves by `leaf`, compound nodes by the chain rule.
template <class Leaf>
DagMap::Rule derivative_rule(Leaf leaf) {
  return [leaf](Expr node, std::span<const Expr> images) {
    if (node.is_number()) return Expr(0);
    if (node.is_symbol()) return leaf(node);
    return chain_rule(node, images);
  };
}

void require_symbol_keys(const std::unordered_map<Expr, Expr>& map, std::string_view what) {
  for (const auto& entry : map) {
    if (!entry.first.is_symbol()) {
      throw UsageError(fmt::format("{}: key '{}' is not a symbol", what, entry.first.str()));
    }
  }
}

DagMap::Rule differentiation_rule(Expr variable) {
  if (!variable.is_symbol()) {
    throw UsageError(fmt::format("diff: the variable '{}' is not a symbol", variable.str()));
  }
  return derivative_rule([variable](Expr s) { return s == variable ? Expr(1) : Expr(0); });
}

DagMap::Rule time_derivative_rule(RateMap rates) {
  require_symbol_keys(rates, "time derivative: rate map");
  return derivative_rule([rates = std::move(rates)](Expr s) {
    if (auto it = rates.find(s); it != rates.end()) return it->second;
    switch (s.symbol_kind()) {
      case SymbolKind::Time:
        return Expr(1);
      case SymbolKind::Parameter:
      case SymbolKind::Free:
        return Expr(0);
      default:
        throw UsageError(fmt::format("time derivative: symbol '{}' ({}) has no rate given",
                                     s.name(), to_string(s.symbol_kind())));
    }
  });
}

DagMap::Rule directional_rule(const std::unordered_map<Expr, Expr>& tangents) {
  return derivative_rule([&tangents](Expr s) {
    auto it = tangents.find(s);
    return it == tangents.end() ? Expr(0) : it->second;
  });
}

// Symbols replaced by their values; a node whose arguments are unchanged is
// kept, any other is rebuilt through its smart constructor.
DagMap::Rule substitution_rule(const std::unordered_map<Expr, Expr>& replacements) {
  return [&replacements](Expr node, std::span<const Expr> images) {
    if (node.is_symbol()) {
      auto it = replacements.find(node);
      return it == replacements.end() ? node : it->second;
    }
    if (std::equal(images.begin(), images.end(), node.args().begin(), node.args().end()))
      return node;
    return make(node.kind(), images);
  };
}

}  // namespace

Expr partial(Expr node, std::size_t i) {
  const auto kind = static_cast<std::size_t>(node.kind());
  if (kPartialByKind[kind] == nullptr) {
    throw UsageError(fmt::format("partial: '{}' is a leaf, it has no arguments", node.str()));
  }
  if (i >= node.args().size()) {
    throw UsageError(fmt::format("partial: '{}' has no argument {}", node.str(), i));
  }
  return kPartialByKind[kind](node, i);
}

Differentiator::Differentiator(Expr variable) : map_(differentiation_rule(variable)) {}

Expr Differentiator::operator()(Expr e) {
  return map_(e);
}

Expr diff(Expr e, Expr variable) {
  return Differentiator(variable)(e);
}

TimeDerivative::TimeDerivative(RateMap rates) : map_(time_derivative_rule(std::move(rates))) {}

Expr TimeDerivative::operator()(Expr e) {
  return map_(e);
}

Expr time_derivative(Expr e, const RateMap& rates) {
  return TimeDerivative(rates)(e);
}

DirectionalDerivative::DirectionalDerivative(std::unordered_map<Expr, Expr> tangents)
    : tangents_(std::move(tangents)), map_(directional_rule(tangents_)) {
  require_symbol_keys(tangents_, "directional derivative");
}

Expr DirectionalDerivative::operator()(Expr e) {
  return map_(e);
}

void DirectionalDerivative::add(Expr symbol, Expr tangent) {
  if (!symbol.is_symbol()) {
    throw UsageError(fmt::format("directional derivative: key '{}' is not a symbol", symbol.str()));
  }
  if (map_.has_mapped(symbol) || !tangents_.try_emplace(symbol, tangent).second) {
    throw UsageError(
        fmt::format("directional derivative: '{}' is already met or given", symbol.name()));
  }
}

Substitution::Substitution(std::unordered_map<Expr, Expr> replacements)
    : replacements_(std::move(replacements)), map_(substitution_rule(replacements_)) {
  require_symbol_keys(replacements_, "substitute");
}

Expr Substitution::operator()(Expr e) {
  return map_(e);
}

void Substitution::add(Expr symbol, Expr value) {
  if (!symbol.is_symbol())
    throw UsageError(fmt::format("substitute: key '{}' is not a symbol", symbol.str()));
  if (map_.has_mapped(symbol) || !replacements_.try_emplace(symbol, value).second) {
    throw UsageError(fmt::format("substitute: '{}' is already met or replaced", symbol.name()));
  }
}

Expr substitute(Expr e, const std::unordered_map<Expr, Expr>& replacements) {
  return Substitution(replacements)(e);
}

}  // namespace symdyn::symbolic
