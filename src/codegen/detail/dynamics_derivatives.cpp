#include <symdyn/codegen/detail/dynamics_derivatives.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include <symdyn/symbolic/jacobian.hpp>

namespace symdyn::codegen::detail {
namespace {

using model::Expr;

struct Form {
  const char* name;
  std::vector<Expr> tau;
  std::size_t operations = 0;  // of tau itself
};

// tau_i = h_i + Σ_k M_ik·qdd_k
std::vector<Expr> mass_matrix_form(const model::Dynamics& dynamics, const std::vector<Expr>& qdd) {
  const std::size_t nq = qdd.size();
  std::vector<Expr> tau(nq);
  for (std::size_t i = 0; i < nq; ++i) {
    std::vector<Expr> terms{dynamics.bias[i]};
    for (std::size_t k = 0; k < nq; ++k) terms.push_back(dynamics.mass_matrix[i * nq + k] * qdd[k]);
    tau[i] = symbolic::add(terms);
  }
  return tau;
}

// The Jacobian d tau/d(q, qd) (nq x 2nq) split into dtau/dq and dtau/dqd.
DynamicsDerivatives split(const symbolic::ChainJacobian& J, std::size_t nq) {
  DynamicsDerivatives d;
  for (std::size_t i = 0; i < nq; ++i) {
    d.dtau_dq.insert(d.dtau_dq.end(), J.entries.begin() + i * 2 * nq, J.entries.begin() + i * 2 * nq + nq);
    d.dtau_dqd.insert(d.dtau_dqd.end(), J.entries.begin() + i * 2 * nq + nq, J.entries.begin() + (i + 1) * 2 * nq);
  }
  d.definitions = J.definitions;
  return d;
}

}  // namespace

DynamicsDerivatives derive_dynamics_derivatives(const model::Dynamics& dynamics, const std::vector<Expr>& q,
                                                const std::vector<Expr>& qd, const std::vector<Expr>& qdd,
                                                const std::vector<symbolic::Definition>& definitions,
                                                const OperationCounter& operations) {
  std::vector<Form> forms{{"recursive Newton-Euler", dynamics.inverse}, {"M qdd + h", mass_matrix_form(dynamics, qdd)}};
  for (Form& f : forms) f.operations = operations(f.tau, definitions);
  std::stable_sort(forms.begin(), forms.end(), [](const Form& a, const Form& b) { return a.operations < b.operations; });
  const bool both = forms[1].operations <= kDerivativeFormRatio * forms[0].operations;
  std::vector<Expr> variables = q;
  variables.insert(variables.end(), qd.begin(), qd.end());
  std::optional<DynamicsDerivatives> best;
  std::size_t best_operations = 0;
  std::vector<std::string> weighed;
  for (std::size_t f = 0; f < (both ? 2 : 1); ++f) {
    DynamicsDerivatives d = split(symbolic::chain_jacobian(forms[f].tau, variables, definitions), q.size());
    std::vector<Expr> outputs = d.dtau_dq;
    outputs.insert(outputs.end(), d.dtau_dqd.begin(), d.dtau_dqd.end());
    std::vector<symbolic::Definition> all = definitions;
    all.insert(all.end(), d.definitions.begin(), d.definitions.end());
    const std::size_t count = operations(outputs, all);
    weighed.push_back(fmt::format("{} {}", forms[f].name, count));
    if (!best || count < best_operations) {
      d.reason = forms[f].name;
      best = std::move(d);
      best_operations = count;
    }
  }
  best->reason = both ? fmt::format("of the {} form (fewer operations): {}, {}", best->reason, weighed[0], weighed[1])
                      : fmt::format("of the {} form, {} operations ({} not differentiated: {} operations of tau "
                                    "against {}, more than {} times)",
                                    best->reason, best_operations, forms[1].name, forms[1].operations,
                                    forms[0].operations, kDerivativeFormRatio);
  return std::move(*best);
}

}  // namespace symdyn::codegen::detail
