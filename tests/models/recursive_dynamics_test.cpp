// The recursive dynamics of every reference model: the emitted
// inverse_dynamics against M·qdd + h from the emitted mass_matrix and
// bias_forces, the emitted forward_dynamics (where the generator chose it)
// against the Cholesky solution of M·qdd = tau - h, and, generated in process
// with the recursive forward dynamics asked for, the interpreter over its
// program wherever it applies. Their operation counts grow linearly on chain_N.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <random>

#include "generated.hpp"
#include "support/emitted_check.hpp"
#include "test_plan.hpp"
#include <symdyn/codegen/generate.hpp>

using namespace symdyn;
using namespace symdyn::testing;
namespace gen = symdyn_generated;

namespace {

// max |a - b| / max |b|: the error relative to the result's scale.
double relative_gap(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

template <class G>
void check_recursive_dynamics() {
  const TestPlan plan = test_plan(G::model);
  INFO(G::model << " " << G::variant);
  STATIC_REQUIRE(G::has_inverse_dynamics);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = G::nq;
  for (int trial = 0; trial < std::max(3, plan.states); ++trial) {
    const ModelState<double> s = random_state_near(rng, G::q_initial, plan.amplitude);
    const double* p = G::param_defaults;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n, n);
    Eigen::VectorXd h(n), tau(n), qdd = Eigen::Map<const Eigen::VectorXd>(s.qdd.data(), n);
    G::mass_matrix(s.t, s.q.data(), p, M.data());
    G::bias_forces(s.t, s.q.data(), s.qd.data(), p, h.data());
    G::inverse_dynamics(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, tau.data());
    const Eigen::VectorXd expected = M * qdd + h;
    INFO("inverse dynamics " << tau.transpose() << "\nM qdd + h " << expected.transpose());
    CHECK(relative_gap(tau, expected) < 1e-12);
    if constexpr (G::has_forward_dynamics) {
      Eigen::VectorXd applied(n), solved(n);
      for (int j = 0; j < n; ++j) applied[j] = u(rng);
      CHECK(G::forward_dynamics(s.t, s.q.data(), s.qd.data(), applied.data(), p, solved.data()) ==
            -1);
      const Eigen::MatrixXd Mc = M;
      const Eigen::VectorXd cholesky = Mc.llt().solve(applied - h);
      INFO("forward dynamics " << solved.transpose() << "\nCholesky " << cholesky.transpose());
      // The residual to rounding; the solutions as far as cond(M) lets them (chain_16: 1e6).
      CHECK(relative_gap(Mc * solved + h, applied) <
            1e-12 * std::max(1.0, (applied - h).norm() / applied.norm()));
      CHECK(relative_gap(solved, cholesky) < 1e-8);
    }
  }
}

// Generated in process with the recursive forward dynamics asked for: where it
// applies, the interpreter over forward_dynamics_pivots gives M⁻¹·(tau - h)
// of the mass_matrix and bias_forces programs, with positive pivots.
void check_forward_dynamics_program(const char* name, const char* variant, bool applies) {
  INFO(name << " " << variant);
  const model::Model m = model::find_definition(name).make(variant);
  codegen::Options options;
  options.simplify = false;  // the generation time; the emitted, simplified code is checked above
  options.dynamics = codegen::DynamicsMethod::recursive;
  const codegen::GeneratedCode code = codegen::generate(m, variant, "x", options);
  CHECK(code.dynamics.recursive == applies);
  if (!applies) return;
  const auto program = [&](const char* entry) -> const codegen::EmittedFunction& {
    for (const auto& f : code.functions) {
      if (f.name == entry) return f;
    }
    FAIL("no entry point " << entry);
    throw;
  };
  const auto n = static_cast<Eigen::Index>(m.coordinates().size());
  std::vector<double> param;
  for (const auto& par : m.parameters()) param.push_back(par.value);
  std::mt19937 rng(13);
  for (int trial = 0; trial < 3; ++trial) {
    const ModelState<double> s = random_state_near(rng, m, test_plan(name).amplitude);
    const auto run = [&](const codegen::EmittedFunction& f) {
      return f.program->evaluate<double>(program_inputs(f, s, param));
    };
    const std::vector<double> Mv = run(program("mass_matrix")), hv = run(program("bias_forces"));
    const std::vector<double> out =
        run(program("forward_dynamics_pivots"));  // qdd (n), pivots (n x 2)
    const Eigen::MatrixXd M = Eigen::Map<const Eigen::MatrixXd>(Mv.data(), n, n);
    const Eigen::VectorXd h = Eigen::Map<const Eigen::VectorXd>(hv.data(), n);
    const Eigen::VectorXd tau =
        Eigen::Map<const Eigen::VectorXd>(s.qdd.data(), n);  // program_inputs: tau = qdd
    const Eigen::VectorXd solved = Eigen::Map<const Eigen::VectorXd>(out.data(), n);
    INFO("forward dynamics " << solved.transpose());
    CHECK(relative_gap(M * solved + h, tau) < 1e-10);
    for (Eigen::Index j = 0; j < n; ++j) CHECK(out[n + 2 * j] > 0.0);
  }
}

std::size_t operations(const char* name, const char* entry) {
  const model::Model m = model::find_definition(name).make("absolute");
  codegen::Options options;
  options.dynamics = codegen::DynamicsMethod::recursive;
  for (const auto& f : codegen::generate(m, "absolute", "x", options).functions) {
    if (f.name == entry) return f.operations.total();
  }
  FAIL("no entry point " << entry);
  return 0;
}

}  // namespace

TEST_CASE("inverse and forward dynamics of the small models", "[models]") {
  check_recursive_dynamics<gen::double_pendulum_absolute>();
  check_recursive_dynamics<gen::double_pendulum_relative>();
  check_recursive_dynamics<gen::robot3d_absolute>();
  check_recursive_dynamics<gen::robot3d_relative>();
  check_recursive_dynamics<gen::slider_crank_inline>();
  check_recursive_dynamics<gen::slider_crank_dependent>();
  check_recursive_dynamics<gen::trike>();
  check_recursive_dynamics<gen::chain_2_relative>();
  check_recursive_dynamics<gen::chain_2_absolute>();
  check_recursive_dynamics<gen::chain_4_relative>();
  check_recursive_dynamics<gen::chain_4_absolute>();
}

TEST_CASE("inverse and forward dynamics of the big models", "[models]") {
  check_recursive_dynamics<gen::amru5_inline>();
  check_recursive_dynamics<gen::amru5_dependent>();
  check_recursive_dynamics<gen::hexapod_tree>();
  check_recursive_dynamics<gen::chain_8_relative>();
  check_recursive_dynamics<gen::chain_8_absolute>();
  check_recursive_dynamics<gen::chain_16_relative>();
  check_recursive_dynamics<gen::chain_16_absolute>();
}

TEST_CASE("the recursive forward dynamics wherever it applies", "[models]") {
  check_forward_dynamics_program("double_pendulum", "relative", true);
  check_forward_dynamics_program("double_pendulum", "absolute",
                                 false);  // q0 moves both rods from the ground
  check_forward_dynamics_program("robot3d", "relative", true);
  check_forward_dynamics_program("trike", "default", true);
  check_forward_dynamics_program("hexapod_tree", "default", true);
  check_forward_dynamics_program("chain_8", "absolute", true);
  check_forward_dynamics_program("slider_crank", "dependent",
                                 false);  // the loop: q0 moves crank and rod
  check_forward_dynamics_program("slider_crank", "inline", false);
}

// The marginal cost of a body stays the same: each added link adds its own
// articulated inertia and Newton-Euler terms; M's entries would add N² / 2.
TEST_CASE("the recursive dynamics of chain_N grow linearly in N", "[models]") {
  for (const char* entry : {"forward_dynamics_pivots", "inverse_dynamics"}) {
    const double n4 = operations("chain_4", entry), n8 = operations("chain_8", entry),
                 n16 = operations("chain_16", entry);
    INFO(entry << ": chain_4 " << n4 << ", chain_8 " << n8 << ", chain_16 " << n16
               << " operations");
    CHECK(n16 - n8 <= 2.1 * (n8 - n4));  // linear: 2x for twice the links added (quadratic: 4x)
    CHECK(n16 / n8 < 2.6);
  }
}
