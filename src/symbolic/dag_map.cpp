#include <algorithm>
#include <utility>

#include <symdyn/symbolic/dag_map.hpp>

namespace symdyn::symbolic {

DagMap::DagMap(Rule rule) : rule_(std::move(rule)) {}

const Node* DagMap::image(Expr e) const {
  const std::uint32_t page = e.id() >> kPageBits;
  return page < pages_.size() && !pages_[page].empty() ? pages_[page][e.id() & (kPage - 1)]
                                                       : nullptr;
}

void DagMap::set_image(Expr e, Expr image) {
  const std::uint32_t page = e.id() >> kPageBits;
  if (page >= pages_.size()) pages_.resize(page + 1);
  if (pages_[page].empty()) pages_[page].assign(kPage, nullptr);
  pages_[page][e.id() & (kPage - 1)] = image.node();
}

Expr DagMap::operator()(Expr e) {
  if (context_ == nullptr) context_ = &Context::current();
  if (context_ != &Context::current())
    throw UsageError("DagMap: used from another context than the one of its first call");

  // Post-order: a frame is a node and the index of its next argument to visit.
  struct Frame {
    Expr node;
    std::size_t next;
  };
  std::vector<Frame> stack;
  std::vector<Expr> images;
  if (image(e) == nullptr) stack.push_back({e, 0});
  while (!stack.empty()) {
    Frame& top = stack.back();
    const auto args = top.node.args();
    while (top.next < args.size() && image(args[top.next]) != nullptr) ++top.next;
    if (top.next < args.size()) {
      stack.push_back({args[top.next], 0});  // invalidates `top`
      continue;
    }
    images.clear();
    for (Expr a : args) images.push_back(Expr(image(a)));
    const Expr node = top.node;
    stack.pop_back();
    // The stack is a path of the DAG, so `node` is not on it twice: map it now.
    set_image(node, rule_(node, images));
  }
  return Expr(image(e));
}

}  // namespace symdyn::symbolic
