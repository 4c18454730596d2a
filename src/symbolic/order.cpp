// The structural order of canonical forms.
#include <algorithm>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {
namespace {

// Numbers first, then symbols, then compound nodes by kind.
int rank(Kind kind) {
  switch (kind) {
    case Kind::Rational:
    case Kind::Real:
      return 0;
    case Kind::Symbol:
      return 1;
    default:
      return 2 + static_cast<int>(kind);
  }
}

}  // namespace

int compare(Expr a, Expr b) {
  if (a == b) return 0;
  const int ra = rank(a.kind());
  const int rb = rank(b.kind());
  if (ra != rb) return ra < rb ? -1 : 1;
  if (a.is_number()) {
    const auto c = compare(a.number(), b.number());
    return c < 0 ? -1 : (c > 0 ? 1 : 0);
  }
  if (a.is_symbol()) return a.symbol_index() < b.symbol_index() ? -1 : 1;
  // Same compound kind: operands lexicographically, then by count.
  const auto xs = a.args();
  const auto ys = b.args();
  const std::size_t n = std::min(xs.size(), ys.size());
  for (std::size_t i = 0; i < n; ++i) {
    const int c = compare(xs[i], ys[i]);
    if (c != 0) return c;
  }
  if (xs.size() != ys.size()) return xs.size() < ys.size() ? -1 : 1;
  return 0;  // unreachable for distinct interned nodes
}

}  // namespace symdyn::symbolic
