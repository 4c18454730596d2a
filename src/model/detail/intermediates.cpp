#include <stdexcept>

#include <symdyn/model/detail/intermediates.hpp>

namespace symdyn::model {

symbolic::Expr IntermediateNames::operator()(symbolic::Expr value, const std::string& name) {
  const auto [coefficient, rest] = symbolic::split_coefficient(value);
  if (rest.kind() != symbolic::Kind::Add) return value;
  auto [it, inserted] = names_.try_emplace(rest, symbolic::Expr());
  if (inserted) {
    // Symbols are interned by name: a second value under one name would be
    // the first one's symbol, silently.
    if (!used_names_.insert(name).second)
      throw std::logic_error("intermediate '" + name + "' named twice");
    it->second = symbolic::symbol(name, symbolic::SymbolKind::Intermediate);
    definitions_.push_back({it->second, rest});
  }
  return symbolic::Expr(coefficient) * it->second;
}

}  // namespace symdyn::model
