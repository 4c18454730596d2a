#include <symdyn/model/trig_reduction.hpp>

#include <algorithm>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/trig_polynomial.hpp>

namespace symdyn::model {
namespace {

// The operations of evaluating M, h and the definitions' values, every node
// counted once (symbolic::operation_cost): a model of the programs' count,
// found without compiling them.
int operations(const std::vector<Expr>& M, const std::vector<Expr>& h,
               const std::vector<symbolic::Definition>& definitions) {
  std::vector<Expr> roots = M;
  roots.insert(roots.end(), h.begin(), h.end());
  for (const symbolic::Definition& d : definitions) roots.push_back(d.value);
  return symbolic::operation_cost(roots);
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
  if (M == dynamics.mass_matrix && h == dynamics.bias && reduced.definitions.size() == dynamics.definitions.size() &&
      std::equal(reduced.definitions.begin(), reduced.definitions.end(), dynamics.definitions.begin(),
                 [](const symbolic::Definition& a, const symbolic::Definition& b) { return a.value == b.value; })) {
    return;  // nothing reduced
  }
  struct Choice {
    int operations;
    bool definitions, M, h;  // reduced or not
  };
  Choice best{-1, false, false, false};
  for (const bool d : {false, true}) {
    for (const bool m : {false, true}) {
      for (const bool b : {false, true}) {
        const int cost = operations(m ? M : dynamics.mass_matrix, b ? h : dynamics.bias,
                                    d ? reduced.definitions : dynamics.definitions);
        if (best.operations < 0 || cost < best.operations) best = {cost, d, m, b};
      }
    }
  }
  if (best.definitions) dynamics.definitions = reduced.definitions;
  if (best.M) dynamics.mass_matrix = M;
  if (best.h) dynamics.bias = h;
}

}  // namespace symdyn::model
