#include <algorithm>

#include <symdyn/model/trig_reduction.hpp>
#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/trig_polynomial.hpp>

namespace symdyn::model {
namespace {

// The operations of evaluating one form of the definitions, of M and of h,
// for each choice of forms (symbolic::operation_cost: every node counted
// once). Each list is walked once, marking the nodes it reaches with its
// bit; a choice then counts the nodes marked by one of its lists.
class ChoiceCost {
 public:
  // Lists 2·k and 2·k + 1 are the given and the reduced forms of part k.
  explicit ChoiceCost(const std::vector<std::vector<Expr>>& lists)
      : marks_(symbolic::Context::current().size(), 0) {
    for (std::size_t i = 0; i < lists.size(); ++i)
      mark(lists[i], static_cast<std::uint8_t>(1U << i));
  }

  // `lists`: a mask of the lists chosen.
  int operator()(unsigned lists) const {
    int cost = 0;
    for (const auto& [id, own] : reached_) cost += (marks_[id] & lists) != 0 ? own : 0;
    return cost;
  }

 private:
  void mark(const std::vector<Expr>& roots, std::uint8_t bit) {
    std::vector<Expr> stack(roots.begin(), roots.end());
    std::vector<Expr> operands;
    while (!stack.empty()) {
      const Expr e = stack.back();
      stack.pop_back();
      std::uint8_t& m = marks_[e.id()];
      if ((m & bit) != 0) continue;
      operands.clear();
      const int own = symbolic::own_cost(e, &operands);
      if (m == 0) reached_.emplace_back(e.id(), own);
      m |= bit;
      stack.insert(stack.end(), operands.begin(), operands.end());
    }
  }

  std::vector<std::uint8_t> marks_;                     // (by node id) the lists that reach it
  std::vector<std::pair<std::uint32_t, int>> reached_;  // each node reached, with its own cost
};

std::vector<Expr> values(const std::vector<symbolic::Definition>& definitions) {
  std::vector<Expr> out;
  for (const symbolic::Definition& d : definitions) out.push_back(d.value);
  return out;
}

}  // namespace

// The reduction is decided expression by expression (symbolic::reduce_pythagorean);
// what M and h then share is another matter: of the reduced and the given forms
// of the definitions, M and h, the combination cheapest in all is kept.
void reduce_trigonometry(Dynamics& dynamics, const Kinematics& kinematics) {
  std::vector<Expr> outputs = dynamics.mass_matrix;
  outputs.insert(outputs.end(), dynamics.bias.begin(), dynamics.bias.end());
  const symbolic::PythagoreanReduction reduced =
      symbolic::reduce_pythagorean(outputs, dynamics.definitions, kinematics.intermediates);
  const auto n = static_cast<std::ptrdiff_t>(dynamics.mass_matrix.size());
  const std::vector<Expr> M(reduced.outputs.begin(), reduced.outputs.begin() + n);
  const std::vector<Expr> h(reduced.outputs.begin() + n, reduced.outputs.end());
  if (M == dynamics.mass_matrix && h == dynamics.bias &&
      reduced.definitions.size() == dynamics.definitions.size() &&
      std::equal(reduced.definitions.begin(), reduced.definitions.end(),
                 dynamics.definitions.begin(),
                 [](const symbolic::Definition& a, const symbolic::Definition& b) {
                   return a.value == b.value;
                 })) {
    return;  // nothing reduced
  }
  struct Choice {
    int operations;
    bool definitions, M, h;  // reduced or not
  };
  const ChoiceCost operations({dynamics.mass_matrix, M, dynamics.bias, h,
                               values(dynamics.definitions), values(reduced.definitions)});
  Choice best{-1, false, false, false};
  for (const bool d : {false, true}) {
    for (const bool m : {false, true}) {
      for (const bool b : {false, true}) {
        const int cost = operations((m ? 2U : 1U) | (b ? 8U : 4U) | (d ? 32U : 16U));
        if (best.operations < 0 || cost < best.operations) best = {cost, d, m, b};
      }
    }
  }
  if (best.definitions) dynamics.definitions = reduced.definitions;
  if (best.M) dynamics.mass_matrix = M;
  if (best.h) dynamics.bias = h;
}

}  // namespace symdyn::model
