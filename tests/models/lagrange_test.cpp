// The emitted equations of motion M(q)·qdd + h(q, qd) = Q against Lagrange's
// equations built from the emitted energies alone (every reference model is
// conservative with gravity its only force):
//   T = ½ Σ m v·v + ½ Ω·I·Ω (Ω = Rᵀw, body axes), V = -Σ m g·x,
//   M_jk = ∂²T/∂qd_j∂qd_k, exact from T at qd = 0, e_j, e_k, e_j + e_k since T
//   is quadratic in qd;
//   h = d/dt(∂T/∂qd) - ∂T/∂q + ∂V/∂q at qdd = 0, with ∂T/∂qd exact (central in
//   qd, step 1) and the derivatives in q and t by central differences.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include "generated.hpp"
#include "support/model_eval.hpp"
#include "test_plan.hpp"

using namespace symdyn::testing;
namespace gen = symdyn_generated;

namespace {

using Vector = std::vector<double>;

template <class G>
class Energies {
 public:
  Energies() { G::inertia(G::param_defaults, mass_.data(), inertia_.data()); }

  double kinetic(double t, const Vector& q, const Vector& qd) const {
    Vector R(9 * G::nbody), x(3 * G::nbody), v(x), w(x);
    G::velocities(t, q.data(), qd.data(), G::param_defaults, R.data(), x.data(), v.data(),
                  w.data());
    double T = 0.0;
    for (int i = 0; i < G::nbody; ++i) {
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Ri(&R[9 * i]),
          Ii(&inertia_[9 * i]);
      const Eigen::Vector3d vi(&v[3 * i]), Omega = Ri.transpose() * Eigen::Vector3d(&w[3 * i]);
      T += 0.5 * mass_[i] * vi.squaredNorm() + 0.5 * Omega.dot(Ii * Omega);
    }
    return T;
  }

  double potential(double t, const Vector& q) const {
    Vector R(9 * G::nbody), x(3 * G::nbody);
    G::positions(t, q.data(), G::param_defaults, R.data(), x.data());
    double V = 0.0;
    for (int i = 0; i < G::nbody; ++i)
      V -= mass_[i] * Eigen::Vector3d(G::gravity).dot(Eigen::Vector3d(&x[3 * i]));
    return V;
  }

 private:
  Vector mass_ = Vector(G::nbody), inertia_ = Vector(9 * G::nbody);
};

Vector plus(Vector a, const Vector& b, double s) {
  for (std::size_t i = 0; i < a.size(); ++i) a[i] += s * b[i];
  return a;
}

Vector unit(std::size_t n, std::size_t j) {
  Vector e(n, 0.0);
  e[j] = 1.0;
  return e;
}

template <class G>
void check_lagrange() {
  constexpr std::size_t n = G::nq;
  const TestPlan plan = test_plan(G::model);
  INFO(G::model << " " << G::variant);
  const Energies<G> energies;
  std::mt19937 rng(21);
  const double eps = 1e-5;
  for (int trial = 0; trial < std::max(2, plan.states); ++trial) {
    const auto s = random_state_near(rng, G::q_initial, plan.amplitude);
    const double t = s.t;
    Eigen::Matrix<double, n, n, Eigen::RowMajor> M_emitted;
    Eigen::Matrix<double, n, 1> h_emitted;
    G::mass_matrix(t, s.q.data(), G::param_defaults, M_emitted.data());
    G::bias_forces(t, s.q.data(), s.qd.data(), G::param_defaults, h_emitted.data());

    auto T = [&](double time, const Vector& q, const Vector& qd) {
      return energies.kinetic(time, q, qd);
    };
    const Vector zero(n, 0.0);
    Vector T_unit(n);
    for (std::size_t j = 0; j < n; ++j) T_unit[j] = T(t, s.q, unit(n, j));
    const double T_zero = T(t, s.q, zero);
    Eigen::Matrix<double, n, n> M;
    for (std::size_t j = 0; j < n; ++j) {
      for (std::size_t k = 0; k < n; ++k) {
        M(j, k) = T(t, s.q, plus(unit(n, j), unit(n, k), 1.0)) - T_unit[j] - T_unit[k] + T_zero;
      }
    }
    CHECK((M - M_emitted).cwiseAbs().maxCoeff() < 1e-10 * std::max(1.0, M.cwiseAbs().maxCoeff()));

    // ∂T/∂qd_j, exact: T is quadratic in qd.
    auto momentum = [&](double time, const Vector& q, std::size_t j) {
      return 0.5 *
             (T(time, q, plus(s.qd, unit(n, j), 1.0)) - T(time, q, plus(s.qd, unit(n, j), -1.0)));
    };
    Eigen::Matrix<double, n, 1> h;
    for (std::size_t j = 0; j < n; ++j) {
      // Along the path at qdd = 0: (t + eps, q + eps·qd), qd fixed.
      const double dp_dt = (momentum(t + eps, plus(s.q, s.qd, eps), j) -
                            momentum(t - eps, plus(s.q, s.qd, -eps), j)) /
                           (2 * eps);
      const Vector ahead = plus(s.q, unit(n, j), eps), behind = plus(s.q, unit(n, j), -eps);
      const double dT_dq = (T(t, ahead, s.qd) - T(t, behind, s.qd)) / (2 * eps);
      const double dV_dq =
          (energies.potential(t, ahead) - energies.potential(t, behind)) / (2 * eps);
      h(j) = dp_dt - dT_dq + dV_dq;
    }
    CHECK((h - h_emitted).cwiseAbs().maxCoeff() < 1e-6 * std::max(1.0, h.cwiseAbs().maxCoeff()));
  }
}

}  // namespace

TEST_CASE("Lagrange: double_pendulum", "[models]") {
  check_lagrange<gen::double_pendulum_absolute>();
  check_lagrange<gen::double_pendulum_relative>();
}
TEST_CASE("Lagrange: robot3d", "[models]") {
  check_lagrange<gen::robot3d_absolute>();
  check_lagrange<gen::robot3d_relative>();
}
TEST_CASE("Lagrange: slider_crank", "[models]") {
  check_lagrange<gen::slider_crank_inline>();
  check_lagrange<gen::slider_crank_dependent>();
}
TEST_CASE("Lagrange: trike", "[models]") {
  check_lagrange<gen::trike>();
}
TEST_CASE("Lagrange: amru5", "[models]") {
  check_lagrange<gen::amru5_inline>();
  check_lagrange<gen::amru5_dependent>();
}
TEST_CASE("Lagrange: hexapod_tree", "[models]") {
  check_lagrange<gen::hexapod_tree>();
}
TEST_CASE("Lagrange: chain_N", "[models]") {
  check_lagrange<gen::chain_2_relative>();
  check_lagrange<gen::chain_2_absolute>();
  check_lagrange<gen::chain_4_relative>();
  check_lagrange<gen::chain_4_absolute>();
  check_lagrange<gen::chain_8_relative>();
  check_lagrange<gen::chain_8_absolute>();
  check_lagrange<gen::chain_16_relative>();
  check_lagrange<gen::chain_16_absolute>();
}
