#pragma once
// The derived equations of motion (model/dynamics.hpp) evaluated at a state,
// and the independent reference they must equal: the direct sums over bodies
// of the kinematics' partial velocities (themselves checked against the 4x4
// products and finite differences, kinematics_checks.hpp):
//
//   M_jk = Σ_i m_i·dv_ij·dv_ik + (R_iᵀ·dw_ij)·I_i·(R_iᵀ·dw_ik)
//   h_j  = Σ_i m_i·(a⁰_i - g)·dv_ij + (I_i·Ω̇⁰_i + Ω_i×(I_i·Ω_i))·(R_iᵀ·dw_ij)
//
// (⁰: at qdd = 0, Ω = Rᵀ·w, Ω̇ = Rᵀ·dw).

#include "support/kinematics_checks.hpp"
#include <symdyn/model/dynamics.hpp>

namespace symdyn::testing {

struct Equations {
  Eigen::MatrixXd M;
  Eigen::VectorXd h;
  Eigen::VectorXd tau,
      forward;  // derived only: inverse dynamics at qdd; forward dynamics at tau = qdd, if derived
};

inline Equations derived_equations(const model::Model& m, const model::Kinematics& k,
                                   const model::Dynamics& d, const ModelState<double>& s) {
  symbolic::Bindings<double> b = bind_state(m, k, s);
  const std::vector<symbolic::Expr> tau = model::generalized_force_symbols(m);
  for (std::size_t j = 0; j < tau.size(); ++j)
    b.emplace(tau[j], s.qdd[j]);  // the forward dynamics' input
  for (const auto& def : d.definitions) b.emplace(def.symbol, symbolic::evaluate(def.value, b));
  const auto n = static_cast<Eigen::Index>(m.coordinates().size());
  Equations e{Eigen::MatrixXd(n, n), Eigen::VectorXd(n), Eigen::VectorXd(n),
              Eigen::VectorXd(d.forward.empty() ? 0 : n)};
  for (Eigen::Index j = 0; j < n; ++j) {
    e.h(j) = symbolic::evaluate(d.bias[j], b);
    e.tau(j) = symbolic::evaluate(d.inverse[j], b);
    if (!d.forward.empty()) e.forward(j) = symbolic::evaluate(d.forward[j], b);
    for (Eigen::Index l = 0; l < n; ++l)
      e.M(j, l) = symbolic::evaluate(d.mass_matrix[j * n + l], b);
  }
  return e;
}

inline Equations equations_by_direct_sums(const model::Model& m, const model::Kinematics& k,
                                          ModelState<double> s) {
  const auto n = static_cast<Eigen::Index>(m.coordinates().size());
  std::fill(s.qdd.begin(), s.qdd.end(), 0.0);
  const symbolic::Bindings<double> b = bind_state(m, k, s);
  const Vector3<double> g = eval3(m.gravity(), b);
  Equations e{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n), {}, {}};
  for (std::size_t i = 0; i < k.bodies.size(); ++i) {
    const model::BodyKinematics& body = k.bodies[i];
    const double mass = symbolic::evaluate(m.bodies()[i].mass(), b);
    const Matrix3<double> I = eval33(m.bodies()[i].inertia(), b);
    const Matrix3<double> R = eval33(body.R, b);
    const Vector3<double> W = R.transpose() * eval3(body.w, b);
    const Vector3<double> dW0 = R.transpose() * eval3(body.dw, b);
    const Vector3<double> force = mass * (eval3(body.a, b) - g);
    const Vector3<double> moment = I * dW0 + W.cross(I * W);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Vector3<double> dv_j = eval3(body.dv_dqd[j], b);
      const Vector3<double> dW_j = R.transpose() * eval3(body.dw_dqd[j], b);
      e.h(j) += force.dot(dv_j) + moment.dot(dW_j);
      for (Eigen::Index l = 0; l < n; ++l) {
        const Vector3<double> dv_l = eval3(body.dv_dqd[l], b);
        const Vector3<double> dW_l = R.transpose() * eval3(body.dw_dqd[l], b);
        e.M(j, l) += mass * dv_j.dot(dv_l) + dW_j.dot(I * dW_l);
      }
    }
  }
  return e;
}

// M, h and M's symmetry (exact: the lower triangle mirrors the upper) against the direct sums.
inline Gap equations_gap(const model::Model& m, const model::Kinematics& k,
                         const model::Dynamics& d, const States& states) {
  Gap gap;
  for (const auto& s : states) {
    const Equations got = derived_equations(m, k, d, s), want = equations_by_direct_sums(m, k, s);
    gap.add(relative_gap(got.M, want.M), "M");
    gap.add(relative_gap(got.h, want.h), "h");
    gap.add((got.M - got.M.transpose()).cwiseAbs().maxCoeff() == 0.0 ? 0.0 : INFINITY,
            "M's symmetry");
    // The recursive inverse dynamics equals M·qdd + h; the forward dynamics (at
    // tau = qdd) solves M·x = tau - h, as far as M's condition allows.
    const Eigen::Map<const Eigen::VectorXd> qdd(s.qdd.data(), got.h.size());
    gap.add(relative_gap(got.tau, Eigen::VectorXd(want.M * qdd + want.h)), "inverse dynamics");
    if (got.forward.size() > 0) {
      const Eigen::VectorXd eigenvalues =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(want.M).eigenvalues();
      if (eigenvalues.minCoeff() > 1e-4 * eigenvalues.maxCoeff()) {
        gap.add(relative_gap(Eigen::VectorXd(want.M * got.forward + want.h), Eigen::VectorXd(qdd)),
                "forward dynamics");
      }
    }
  }
  return gap;
}

}  // namespace symdyn::testing
