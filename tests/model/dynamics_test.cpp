// The equations of motion (composite inertias about each tree's point O,
// model/dynamics.hpp) against the direct sums over bodies, evaluated
// numerically from the kinematics' partial velocities:
//
//   M_jk = Σ_i m_i·dv_ij·dv_ik + (R_iᵀ·dw_ij)·I_i·(R_iᵀ·dw_ik)
//   h_j  = Σ_i m_i·(a⁰_i - g)·dv_ij + (I_i·Ω̇⁰_i + Ω_i×(I_i·Ω_i))·(R_iᵀ·dw_ij)
//
// (⁰: at qdd = 0, Ω = Rᵀ·w, Ω̇ = Rᵀ·dw) on every registered model, and on a
// floating tree with full inertia tensors, shared and dependent coordinates,
// a body driven by a dependent parameter alone (one twist direction for two
// coordinates), a body turned by one angle of three coordinates and time (one
// screw), a body alone, and its base far from the origin.
#include <catch2/catch.hpp>

#include "model/dynamics.hpp"
#include "support/kinematics_checks.hpp"

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;

namespace {

model::Mat3 tensor(double xx, double yy, double zz, double xy, double xz, double yz) {
  return {Expr(xx), Expr(xy), Expr(xz), Expr(xy), Expr(yy), Expr(yz), Expr(xz), Expr(yz), Expr(zz)};
}

void floating_tree(model::Model& m, std::string_view) {
  using namespace symdyn::model;
  const auto q = m.coordinates(9);
  const Expr p = m.dependent("p", 0.2 + 0.1 * sin(q[6] - q[7]));
  m.body("base").mass(3.0).inertia(tensor(0.4, 0.5, 0.6, 0.05, -0.02, 0.03))
      .motion(Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]));
  m.body("arm").mass(1.2).inertia(tensor(0.02, 0.09, 0.1, 0.004, 0.001, -0.003)).relative_to("base")
      .motion(Tdisp(0.3, 0.1, -0.2) * Troty(q[6]) * Tdisp(0.4, 0, 0));
  m.body("hand").mass(0.4).inertia(0.001, 0.01, 0.01).relative_to("arm")  // a rod: one repeated moment
      .motion(Trotx(q[7]) * Tdisp(q[8], 0, 0.1));
  m.body("ball").mass(0.7).inertia(0.003, 0.003, 0.003).relative_to("base")  // coordinates shared with arm
      .motion(Trotz(q[6] + q[7]) * Tdisp(p, 0, 0.05));
  m.body("slider").mass(0.3).inertia(0.002, 0.004, 0.005).relative_to("arm")  // driven by p alone
      .motion(Tdisp(p, 0, 0.05) * Troty(2 * p));
  m.body("link").mass(0.5).inertia(tensor(0.004, 0.006, 0.007, 0.001, 0.0005, -0.001)).relative_to("arm")
      .motion(Tdisp(0.1, 0.05, 0) * Troty(p - q[8] + 0.5 * m.time()) * Tdisp(0.2, 0, 0));  // one screw, 3 coordinates
  m.body("alone").mass(0.9).inertia(0.01, 0.02, 0.03).motion(Trotz(q[7]) * Tdisp(1, 0, 0) * Trotx(q[5]));
  m.gravity(0, 0, -9.81);
}

const model::Registration registration({"floating_tree", {"default"}, floating_tree});

struct Equations {
  Eigen::MatrixXd M;
  Eigen::VectorXd h;
};

Equations derived(const model::Model& m, const model::Kinematics& k, const model::Dynamics& d,
                  const ModelState<double>& s) {
  symbolic::Bindings<double> b = bind_state(m, k, s);
  for (const auto& def : d.definitions) b.emplace(def.symbol, symbolic::evaluate(def.value, b));
  const auto n = static_cast<Eigen::Index>(m.coordinates().size());
  Equations e{Eigen::MatrixXd(n, n), Eigen::VectorXd(n)};
  for (Eigen::Index j = 0; j < n; ++j) {
    e.h(j) = symbolic::evaluate(d.bias[j], b);
    for (Eigen::Index l = 0; l < n; ++l) e.M(j, l) = symbolic::evaluate(d.mass_matrix[j * n + l], b);
  }
  return e;
}

Equations direct_sums(const model::Model& m, const model::Kinematics& k, ModelState<double> s) {
  const auto n = static_cast<Eigen::Index>(m.coordinates().size());
  std::fill(s.qdd.begin(), s.qdd.end(), 0.0);
  const symbolic::Bindings<double> b = bind_state(m, k, s);
  const Vector3<double> g = eval3(m.gravity(), b);
  Equations e{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
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

void check_equations(const std::string& name, const std::string& variant, double position_scale) {
  const model::Model m = model::find_definition(name).make(variant);
  std::mt19937 rng(5);
  for (bool simplify : {false, true}) {
    const model::Kinematics k = derive_for_test(m, simplify, true);
    const model::Dynamics d = model::derive_dynamics(m, k);
    for (int trial = 0; trial < 5; ++trial) {
      ModelState<double> s = random_state(rng, m.coordinates().size());
      if (name == "floating_tree") {
        for (int c = 0; c < 3; ++c) s.q[c] *= position_scale;
      }
      const Equations got = derived(m, k, d, s), want = direct_sums(m, k, s);
      INFO(name << " " << variant << " simplify=" << simplify << " base at " << position_scale);
      CHECK(relative_gap(got.M, want.M) < 1e-12);
      CHECK(relative_gap(got.h, want.h) < 1e-12);
      CHECK((got.M - got.M.transpose()).cwiseAbs().maxCoeff() == 0.0);
    }
  }
}

}  // namespace

TEST_CASE("equations of motion by composite inertias equal the direct sums over bodies", "[dynamics]") {
  for (const auto& definition : model::registry()) {
    for (const auto& variant : definition.variants) check_equations(definition.name, variant, 1.0);
  }
}

TEST_CASE("the equations of motion stay accurate with the floating base far from the origin", "[dynamics]") {
  check_equations("floating_tree", "default", 1e4);
}

TEST_CASE("the equations of motion need symbolic partial velocities", "[dynamics]") {
  const model::Model m = model::find_definition("floating_tree").make();
  CHECK_THROWS_WITH(model::derive_dynamics(m, derive_for_test(m, false, false)),
                    Catch::Contains("need symbolic partial velocities"));
}
