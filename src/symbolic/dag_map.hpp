#pragma once
// A memoized bottom-up map over an expression DAG, shared by differentiation,
// the total time derivative and substitution.
//
// Why: a DAG with shared subexpressions can be exponentially larger as a tree,
// so every pass that maps nodes to nodes must visit each node once. The images
// live in a side table indexed by node id (ids are dense per context), never in
// the nodes. The traversal is iterative, so deep DAGs cannot overflow the stack.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {

class DagMap {
 public:
  // rule(node, images) returns the image of `node`, given the images of its
  // arguments (empty for leaves), in the order of node.args().
  using Rule = std::function<Expr(Expr node, std::span<const Expr> images)>;

  explicit DagMap(Rule rule);

  // The image of e. Nodes seen by earlier calls are not mapped again. A DagMap
  // belongs to the context current at its first call: calling it from another
  // context throws UsageError.
  Expr operator()(Expr e);
  // Whether an earlier call has mapped e.
  bool has_mapped(Expr e) const { return image(e) != nullptr; }

 private:
  const Node* image(Expr e) const;
  void set_image(Expr e, Expr image);

  Rule rule_;
  // By node id, in pages of kPage ids allocated when first written (nullptr
  // while not mapped): a map of a few nodes of a large context, as a one-off
  // derivative is, allocates a few pages, not a table of every id.
  static constexpr std::uint32_t kPageBits = 10;
  static constexpr std::uint32_t kPage = 1U << kPageBits;
  std::vector<std::vector<const Node*>> pages_;
  const Context* context_ = nullptr;
};

}  // namespace symdyn::symbolic
