// The recursive derivatives of the inverse dynamics (model/dynamics_derivatives.hpp)
// against two independent references at random states: forward-mode
// differentiation of the recursive Newton-Euler program (symbolic::chain_jacobian
// of Dynamics::inverse, the generator's other form), to rounding, and central
// differences of the evaluated tau with Richardson extrapolation; their mass
// matrix (S_k·P_i) against the dynamics' own expressions of M. Every
// registered model where the algorithm applies, and a list of those where it
// must (a model losing it would otherwise pass silently).
#include <catch2/catch.hpp>
#include <random>
#include <set>

#include "support/equations_checks.hpp"
#include <symdyn/model/dynamics_derivatives.hpp>
#include <symdyn/symbolic/jacobian.hpp>

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;

namespace {

// Evaluates expressions at a state through the kinematics', the dynamics'
// and some derivatives' definitions.
struct AtState {
  symbolic::Bindings<double> bindings;

  AtState(const model::Model& m, const model::Kinematics& k, const model::Dynamics& d,
          const ModelState<double>& s)
      : bindings(bind_state(m, k, s)) {
    for (const Expr& tau : model::generalized_force_symbols(m))
      bindings.emplace(tau, 0.0);  // the forward dynamics' input, among the definitions
    define(d.definitions);
  }

  void define(const std::vector<symbolic::Definition>& definitions) {
    for (const auto& def : definitions)
      bindings.emplace(def.symbol, symbolic::evaluate(def.value, bindings));
  }

  Eigen::MatrixXd matrix(const std::vector<Expr>& entries, Eigen::Index rows) {
    const Eigen::Index cols = static_cast<Eigen::Index>(entries.size()) / rows;
    symbolic::Evaluator<double> eval(bindings);
    Eigen::MatrixXd out(rows, cols);
    for (Eigen::Index r = 0; r < rows; ++r) {
      for (Eigen::Index c = 0; c < cols; ++c) out(r, c) = eval(entries[r * cols + c]);
    }
    return out;
  }
};

Eigen::VectorXd tau(const model::Model& m, const model::Kinematics& k, const model::Dynamics& d,
                    const ModelState<double>& s) {
  AtState at(m, k, d, s);
  return at.matrix(d.inverse, static_cast<Eigen::Index>(d.inverse.size()));
}

// d tau / d x_j (x = q or qd) by central differences at steps h and h/2, Richardson-extrapolated.
Eigen::MatrixXd richardson(const model::Model& m, const model::Kinematics& k,
                           const model::Dynamics& d, const ModelState<double>& s, bool rates) {
  const std::size_t nq = s.q.size();
  Eigen::MatrixXd out(nq, nq);
  const auto central = [&](std::size_t j, double h) {
    ModelState<double> ahead = s, behind = s;
    (rates ? ahead.qd : ahead.q)[j] += h;
    (rates ? behind.qd : behind.q)[j] -= h;
    return Eigen::VectorXd((tau(m, k, d, ahead) - tau(m, k, d, behind)) / (2 * h));
  };
  for (std::size_t j = 0; j < nq; ++j) {
    const double h = 1e-3;
    out.col(static_cast<Eigen::Index>(j)) = (4 * central(j, h / 2) - central(j, h)) / 3;
  }
  return out;
}

double scaled_gap(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
  return (got - want).cwiseAbs().maxCoeff() / std::max(1.0, want.cwiseAbs().maxCoeff());
}

// Whether the algorithm applies; if so, its derivatives against both references
// and its M against the dynamics'.
bool check_model(const model::Model& m) {
  const model::Kinematics k = derive_for_test(m, false, true);
  const model::Dynamics d = model::derive_dynamics(m, k);
  const model::InverseDynamicsDerivatives r = model::derive_inverse_dynamics_derivatives(m, k);
  INFO(m.name() << ": " << r.why_not);
  if (!r.why_not.empty()) return false;
  const std::size_t nq = m.coordinates().size();
  const auto n = static_cast<Eigen::Index>(nq);
  std::vector<Expr> x;
  for (const auto& c : m.coordinates()) x.push_back(c.q);
  for (const auto& c : m.coordinates()) x.push_back(c.qd);
  const symbolic::ChainJacobian forward = symbolic::chain_jacobian(d.inverse, x, d.definitions);
  std::mt19937 rng(26);
  for (int trial = 0; trial < 3; ++trial) {
    const ModelState<double> s = random_state_near(rng, m, 1.0);
    AtState at(m, k, d, s);
    at.define(forward.definitions);
    at.define(r.definitions);
    const Eigen::MatrixXd J = at.matrix(forward.entries, n);
    const Eigen::MatrixXd dq = at.matrix(r.dtau_dq, n), dqd = at.matrix(r.dtau_dqd, n);
    const Eigen::MatrixXd M = at.matrix(r.mass_matrix, n);
    INFO("trial " << trial);
    CHECK(scaled_gap(M, at.matrix(d.mass_matrix, n)) < 1e-12);
    CHECK(M == M.transpose());
    CHECK(scaled_gap(dq, J.leftCols(n)) < 1e-12);
    CHECK(scaled_gap(dqd, J.rightCols(n)) < 1e-12);
    CHECK(scaled_gap(dq, richardson(m, k, d, s, false)) < 1e-8);
    CHECK(scaled_gap(dqd, richardson(m, k, d, s, true)) < 1e-8);
  }
  return true;
}

}  // namespace

TEST_CASE("the recursive derivatives of the inverse dynamics equal forward mode and differences",
          "[dynamics][derivatives]") {
  const std::set<std::string> must{"double_pendulum absolute",
                                   "double_pendulum relative",
                                   "chain_2 relative",
                                   "chain_2 absolute",
                                   "chain_4 relative",
                                   "chain_4 absolute",
                                   "chain_8 relative",
                                   "chain_8 absolute",
                                   "robot3d absolute",
                                   "robot3d relative",
                                   "trike default",
                                   "hexapod_tree default"};
  std::set<std::string> applied;
  for (const auto& definition : model::registry()) {
    if (definition.name == "chain_16" || definition.name == "chain_32" ||
        definition.name == "chain_64")
      continue;  // chain_8 has every case of a chain, the longer ones only cost time
    for (const auto& variant : definition.variants) {
      if (check_model(model::find_definition(definition.name).make(variant)))
        applied.insert(definition.name + " " + variant);
    }
  }
  for (const std::string& model : must) {
    INFO(model);
    CHECK(applied.contains(model));
  }
}

// A cart on a tilted rail (prismatic) carrying a pendulum that a second slider
// runs along, turning about an axis out of the plane: translations before and
// after rotations, in 3D.
TEST_CASE("the recursive derivatives apply through prismatic joints", "[dynamics][derivatives]") {
  using namespace symdyn::model;
  Model m("cart_pendulum");
  const auto q = m.coordinates(4);
  m.body("cart").mass(2.0).inertia(0.1, 0.2, 0.3).motion(Trotz(0.3) * Tdisp(q[0], 0, 0));
  m.body("pendulum")
      .mass(1.0)
      .inertia(0.05, 0.02, 0.04)
      .motion(Trotz(0.3) * Tdisp(q[0], 0, 0) * Trotx(0.2) * Troty(q[1]) * Tdisp(0, 0, -0.5));
  m.body("slider")
      .mass(0.5)
      .inertia(0.01, 0.01, 0.02)
      .motion(Trotz(0.3) * Tdisp(q[0], 0, 0) * Trotx(0.2) * Troty(q[1]) * Tdisp(0.1, 0, -q[2]) *
              Trotz(q[3]) * Tdisp(0.2, 0.1, 0));
  m.gravity(0, 0, -9.81);
  CHECK(check_model(m));
}

TEST_CASE("the recursive derivatives say why they do not apply", "[dynamics][derivatives]") {
  model::Model m("shared_angle");
  using namespace symdyn::model;
  const auto q = m.coordinates(2);
  m.body("a").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Trotz(q[0] + q[1]) * Tdisp(1, 0, 0));
  m.body("b").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Trotz(q[1]) * Tdisp(1, 0, 0));
  m.gravity(0, -9.81, 0);
  const model::Kinematics k = derive_for_test(m, false, true);
  const model::InverseDynamicsDerivatives r = model::derive_inverse_dynamics_derivatives(m, k);
  CHECK(r.why_not.find("coordinate 'q1' moves body 'b'") != std::string::npos);
  CHECK(r.dtau_dq.empty());
  CHECK(r.mass_matrix.empty());
}
