#include <unordered_set>

#include <symdyn/codegen/detail/constraint_derivatives.hpp>
#include <symdyn/symbolic/jacobian.hpp>

namespace symdyn::codegen::detail {

using model::Expr;

ConstraintDerivatives derive_constraint_derivatives(
    const model::Constraints& c, const std::vector<Expr>& q, const std::vector<Expr>& qd,
    const std::vector<Expr>& qdd, const std::vector<Expr>& mu,
    const std::vector<symbolic::Definition>& definitions) {
  const std::size_t nc = c.g.size(), nq = q.size(), nind = nq - nc;
  // g_x (nc x nq) row-major from g_q (nc x nind) and g_p (nc x nc).
  const auto g_x = [&](std::size_t i, std::size_t j) {
    return j < nind ? c.g_q[i * nind + j] : c.g_p[i * nc + j - nind];
  };
  // Outputs: a_i = Σ_j g_x,ij·xdd_j + gamma_i (nc), then (mu·g)_x,j = Σ_i mu_i·g_x,ij (nq).
  std::vector<Expr> outputs;
  for (std::size_t i = 0; i < nc; ++i) {
    std::vector<Expr> terms{c.gamma[i]};
    for (std::size_t j = 0; j < nq; ++j) terms.push_back(g_x(i, j) * qdd[j]);
    outputs.push_back(symbolic::add(terms));
  }
  for (std::size_t j = 0; j < nq; ++j) {
    std::vector<Expr> terms;
    for (std::size_t i = 0; i < nc; ++i) terms.push_back(mu[i] * g_x(i, j));
    outputs.push_back(symbolic::add(terms));
  }
  std::vector<Expr> variables = q;
  variables.insert(variables.end(), qd.begin(), qd.end());
  const symbolic::ChainJacobian J = symbolic::chain_jacobian(outputs, variables, definitions);
  // J.entries[o·2nq + k]: ∂output_o/∂q_k, then ∂output_o/∂qd_k.
  ConstraintDerivatives d;
  const auto row = [&](std::size_t o, std::size_t first, std::vector<Expr>& out) {
    const auto begin = J.entries.begin() + static_cast<std::ptrdiff_t>(o * 2 * nq + first);
    out.insert(out.end(), begin, begin + static_cast<std::ptrdiff_t>(nq));
  };
  for (std::size_t i = 0; i < nc; ++i) {
    row(i, 0, d.a_x);
    row(i, nq, d.a_xd);
  }
  for (std::size_t j = 0; j < nq; ++j) row(nc + j, 0, d.hessian);
  // A derivative of a defined symbol that the definitions hold already is not defined again.
  std::unordered_set<Expr> defined;
  for (const symbolic::Definition& def : definitions) defined.insert(def.symbol);
  for (const symbolic::Definition& def : J.definitions) {
    if (!defined.contains(def.symbol)) d.definitions.push_back(def);
  }
  return d;
}

}  // namespace symdyn::codegen::detail
