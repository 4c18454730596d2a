#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <unordered_set>

#include <symdyn/codegen/detail/dynamics_derivatives.hpp>
#include <symdyn/symbolic/jacobian.hpp>

namespace symdyn::codegen::detail {
namespace {

using model::Expr;

// The third form's name (model/dynamics_derivatives.hpp).
constexpr const char* kRecursiveDerivatives = "recursive derivatives";

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
    d.dtau_dq.insert(d.dtau_dq.end(), J.entries.begin() + i * 2 * nq,
                     J.entries.begin() + i * 2 * nq + nq);
    d.dtau_dqd.insert(d.dtau_dqd.end(), J.entries.begin() + i * 2 * nq + nq,
                      J.entries.begin() + (i + 1) * 2 * nq);
  }
  d.definitions = J.definitions;
  return d;
}

// ∂v/∂q, ∂w/∂q, ∂(dv/dqd)/∂q and ∂(dw/dqd)/∂q of every body into d, in one
// sweep per coordinate; a derivative of a defined symbol that tau's already
// has (the same symbol, of the same value) is not defined again.
void add_kinematics_derivatives(const model::Kinematics& k, const std::vector<Expr>& q,
                                const std::vector<symbolic::Definition>& definitions,
                                DynamicsDerivatives& d) {
  if (k.bodies.empty() || k.bodies.front().dv_dqd.empty()) return;  // numeric partial velocities
  d.kinematics = true;
  const std::size_t nq = q.size();
  std::vector<Expr> outputs;  // v, w (nbody x 3 each), then dv, dw (nbody x nq x 3 each)
  for (const auto& b : k.bodies) outputs.insert(outputs.end(), b.v.begin(), b.v.end());
  for (const auto& b : k.bodies) outputs.insert(outputs.end(), b.w.begin(), b.w.end());
  for (const auto& b : k.bodies) {
    for (const model::Vec3& v : b.dv_dqd) outputs.insert(outputs.end(), v.begin(), v.end());
  }
  for (const auto& b : k.bodies) {
    for (const model::Vec3& v : b.dw_dqd) outputs.insert(outputs.end(), v.begin(), v.end());
  }
  const symbolic::ChainJacobian J = symbolic::chain_jacobian(outputs, q, definitions);
  // J.entries[o·nq + k] = ∂output_o/∂q_k: reordered so that k comes before the vector's component.
  const std::size_t nb = k.bodies.size();
  const auto take = [&](std::size_t first, std::size_t vectors, std::vector<Expr>& out) {
    for (std::size_t vec = 0; vec < vectors; ++vec) {
      for (std::size_t j = 0; j < nq; ++j) {
        for (std::size_t c = 0; c < 3; ++c)
          out.push_back(J.entries[(first + 3 * vec + c) * nq + j]);
      }
    }
  };
  take(0, nb, d.dv_dq);
  take(3 * nb, nb, d.dw_dq);
  take(6 * nb, nb * nq, d.ddv_dq);
  take(6 * nb + 3 * nb * nq, nb * nq, d.ddw_dq);
  std::unordered_set<Expr> defined;
  for (const symbolic::Definition& def : d.definitions) defined.insert(def.symbol);
  for (const symbolic::Definition& def : J.definitions) {
    if (!defined.contains(def.symbol)) d.definitions.push_back(def);
  }
}

}  // namespace

DynamicsDerivatives derive_dynamics_derivatives(
    const model::Dynamics& dynamics, model::InverseDynamicsDerivatives recursive,
    const model::Kinematics* kinematics, const std::vector<Expr>& q, const std::vector<Expr>& qd,
    const std::vector<Expr>& qdd, const std::vector<symbolic::Definition>& definitions,
    const OperationCounter& operations) {
  std::vector<Form> forms{{"recursive Newton-Euler", dynamics.inverse},
                          {"M qdd + h", mass_matrix_form(dynamics, qdd)}};
  for (Form& f : forms) f.operations = operations(f.tau, definitions);
  std::stable_sort(forms.begin(), forms.end(),
                   [](const Form& a, const Form& b) { return a.operations < b.operations; });
  const bool both = forms[1].operations <= kDerivativeFormRatio * forms[0].operations;
  std::vector<Expr> variables = q;
  variables.insert(variables.end(), qd.begin(), qd.end());
  std::optional<DynamicsDerivatives> best;
  std::size_t best_operations = 0;
  std::vector<std::string> weighed;
  for (std::size_t f = 0; f < (both ? 2 : 1); ++f) {
    DynamicsDerivatives d =
        split(symbolic::chain_jacobian(forms[f].tau, variables, definitions), q.size());
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
  std::string reason =
      both ? fmt::format("of the {} form (fewer operations): {}, {}", best->reason, weighed[0],
                         weighed[1])
           : fmt::format(
                 "of the {} form, {} operations ({} not differentiated: {} operations of tau "
                 "against {}, more than {} times)",
                 best->reason, best_operations, forms[1].name, forms[1].operations,
                 forms[0].operations, kDerivativeFormRatio);
  if (!recursive.why_not.empty()) {
    reason += fmt::format("; recursive derivatives do not apply: {}", recursive.why_not);
  } else {
    std::vector<Expr> outputs = recursive.dtau_dq;
    outputs.insert(outputs.end(), recursive.dtau_dqd.begin(), recursive.dtau_dqd.end());
    std::vector<symbolic::Definition> all = definitions;
    all.insert(all.end(), recursive.definitions.begin(), recursive.definitions.end());
    const std::size_t count = operations(outputs, all);
    if (count < best_operations) {
      reason = fmt::format("of the recursive derivatives form (fewer operations): {} {}, {} {}",
                           kRecursiveDerivatives, count, best->reason, best_operations);
      best = DynamicsDerivatives{};
      best->dtau_dq = std::move(recursive.dtau_dq);
      best->dtau_dqd = std::move(recursive.dtau_dqd);
      best->mass_matrix = std::move(recursive.mass_matrix);
      best->definitions = std::move(recursive.definitions);
    } else {
      reason += fmt::format("; {} {}", kRecursiveDerivatives, count);
    }
  }
  if (best->mass_matrix.empty()) best->mass_matrix = dynamics.mass_matrix;
  best->reason = std::move(reason);
  if (kinematics) add_kinematics_derivatives(*kinematics, q, definitions, *best);
  return std::move(*best);
}

}  // namespace symdyn::codegen::detail
