#pragma once
// A side table indexed by node id, for the memos of the passes that visit a
// node once (simplify, expand, rewrite).
//
// Why: ids are dense per context, so a vector indexed by id answers a lookup
// with one load, where a hash map hashes, probes and allocates a node per
// entry; the simplifier looks its memos up millions of times. The table grows
// to the largest id it has seen.
#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic::detail {

// T{} means "no entry" (nullptr for the image of a node, 0 for a mark).
template <class T>
class NodeTable {
  static_assert(std::is_trivially_copyable_v<T>, "NodeTable holds plain values");

 public:
  T get(Expr e) const { return e.id() < values_.size() ? values_[e.id()] : T{}; }
  T& at(Expr e) {
    const std::uint32_t id = e.id();
    if (id >= values_.size())
      values_.resize(std::max<std::size_t>(id + 1, 2 * values_.size()), T{});
    return values_[id];
  }

 private:
  std::vector<T> values_;  // (by node id)
};

// The image of each node mapped so far.
class ExprMemo {
 public:
  const Node* find(Expr e) const { return images_.get(e); }
  void set(Expr e, Expr image) { images_.at(e) = image.node(); }

 private:
  NodeTable<const Node*> images_;
};

}  // namespace symdyn::symbolic::detail
