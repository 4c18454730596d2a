#include "model/dynamics.hpp"

#include <fmt/format.h>

#include <unordered_map>

#include "symbolic/diff.hpp"

namespace symdyn::model {
namespace {

Vec3 substitute(const Vec3& v, symbolic::Substitution& s) { return {s(v[0]), s(v[1]), s(v[2])}; }

Vec3 times(const Mat3& I, const Vec3& v) { return I * v; }

}  // namespace

Dynamics derive_dynamics(const Model& model, const Kinematics& k) {
  const std::size_t nq = model.coordinates().size();
  if (!k.bodies.empty() && k.bodies.front().dv_dqd.size() != nq) {
    throw ModelError(fmt::format("model '{}': the equations of motion need symbolic partial velocities", model.name()));
  }
  Dynamics d;
  // qdd -> 0; each pdd_k -> pdd⁰_k and each intermediate that depends on an
  // acceleration -> its own value at qdd = 0, defined in order on the ones before.
  std::unordered_map<Expr, Expr> zero;
  for (const Coordinate& c : model.coordinates()) zero.emplace(c.qdd, Expr(0));
  symbolic::Substitution at_zero_qdd(std::move(zero));
  // A value that is a number or a symbol replaces the symbol as it is, so that
  // zeros cancel the terms they multiply.
  auto define_at_rest = [&](Expr symbol, Expr value, symbolic::SymbolKind kind) {
    const Expr at_rest_value = at_zero_qdd(value);
    if (at_rest_value == value) return;
    if (at_rest_value.is_number() || at_rest_value.is_symbol()) return at_zero_qdd.add(symbol, at_rest_value);
    const Expr at_rest = symbolic::symbol(fmt::format("{}__0", symbol.name()), kind);
    d.zero_qdd_definitions.push_back({at_rest, at_rest_value});
    at_zero_qdd.add(symbol, at_rest);
  };
  for (const DependentKinematics& p : k.dependents) {
    define_at_rest(p.symbols.acceleration, p.acceleration, symbolic::SymbolKind::DependentAcceleration);
  }
  for (const symbolic::Definition& i : k.intermediates) {
    define_at_rest(i.symbol, i.value, symbolic::SymbolKind::Intermediate);
  }

  // Each entry sums one term per body: the terms are gathered and added once,
  // since adding them one by one would rebuild (and re-sort) the growing sum
  // at every body, quadratic in the number of bodies.
  std::vector<std::vector<Expr>> mass_terms(nq * nq), bias_terms(nq);
  const Vec3& g = model.gravity();
  for (std::size_t i = 0; i < k.bodies.size(); ++i) {
    const BodyKinematics& b = k.bodies[i];
    const Body& body = model.bodies()[i];
    const Expr m = body.mass();
    const Mat3& I = body.inertia();
    // Partial angular velocities in body axes.
    std::vector<Vec3> dW;
    for (const Vec3& dw : b.dw_dqd) dW.push_back(transpose_times(b.R, dw));
    std::vector<Vec3> I_dW;
    for (const Vec3& v : dW) I_dW.push_back(times(I, v));
    const Vec3 W = transpose_times(b.R, b.w);
    const Vec3 dW0 = transpose_times(b.R, substitute(b.dw, at_zero_qdd));
    const Vec3 moment = times(I, dW0) + cross(W, times(I, W));
    const Vec3 force_per_mass = substitute(b.a, at_zero_qdd) - g;
    for (std::size_t j = 0; j < nq; ++j) {
      bias_terms[j].push_back(m * dot(force_per_mass, b.dv_dqd[j]) + dot(moment, dW[j]));
      for (std::size_t l = j; l < nq; ++l) {
        mass_terms[j * nq + l].push_back(m * dot(b.dv_dqd[j], b.dv_dqd[l]) + dot(dW[j], I_dW[l]));
      }
    }
  }
  d.mass_matrix.assign(nq * nq, Expr(0));
  d.bias.assign(nq, Expr(0));
  for (std::size_t j = 0; j < nq; ++j) {
    d.bias[j] = symbolic::add(bias_terms[j]);
    for (std::size_t l = j; l < nq; ++l) d.mass_matrix[j * nq + l] = symbolic::add(mass_terms[j * nq + l]);
  }
  for (std::size_t j = 0; j < nq; ++j) {
    for (std::size_t l = 0; l < j; ++l) d.mass_matrix[j * nq + l] = d.mass_matrix[l * nq + j];
  }
  return d;
}

}  // namespace symdyn::model
