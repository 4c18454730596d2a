// SpdSolver against Eigen's LLT, on both sides of its switch to Eigen's
// blocked factorization, and what it refuses.

#include <catch2/catch.hpp>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <cmath>
#include <limits>

#include "runtime/spd_solver.hpp"

using namespace symdyn::runtime;

namespace {

// A random SPD matrix with condition number about 10^decades.
Matrix random_spd(int n, double decades) {
  const Matrix A = Matrix::Random(n, n);
  const Eigen::HouseholderQR<Matrix> qr(A);
  const Matrix Q = qr.householderQ();
  Vector d(n);
  for (int i = 0; i < n; ++i) d(i) = std::pow(10.0, n > 1 ? -decades * i / (n - 1) : 0.0);
  return Q * d.asDiagonal() * Q.transpose();
}

}  // namespace

TEST_CASE("SpdSolver solves as Eigen's LLT does, below and above its switch", "[runtime][solver]") {
  for (int n : {1, 2, 3, 5, 13, 24, SpdSolver::kLoopUpTo, SpdSolver::kLoopUpTo + 1, 64}) {
    CAPTURE(n);
    const Matrix M = random_spd(n, 3.0);
    const Vector b = Vector::Random(n);
    SpdSolver solver(n);
    REQUIRE(solver.factor(M));
    Vector x = b;
    solver.solve_in_place(x);
    const Vector reference = Eigen::LLT<Matrix>(M).solve(b);
    CHECK((x - reference).norm() <= 1e-10 * reference.norm());
    CHECK((M * x - b).norm() <= 1e-12 * 1e3 * b.norm());
    // The pivots D_k = L_kk² of an SPD matrix lie between its extreme
    // eigenvalues (here 1e-3 and 1).
    CHECK(solver.smallest_pivot() >= 1e-3 * (1.0 - 1e-9));
    CHECK(solver.largest_pivot() <= 1.0 + 1e-12);
  }
}

TEST_CASE("SpdSolver refuses indefinite, singular and non-finite matrices", "[runtime][solver]") {
  for (int n : {3, SpdSolver::kLoopUpTo + 5}) {
    CAPTURE(n);
    SpdSolver solver(n);
    Matrix M = random_spd(n, 1.0);
    REQUIRE(solver.factor(M));
    Matrix indefinite = M;
    indefinite(n - 1, n - 1) = -1.0;
    CHECK_FALSE(solver.factor(indefinite));
    // A coordinate without inertia: singular to working precision.
    Matrix singular = M;
    singular.row(1).setZero();
    singular.col(1).setZero();
    singular(1, 1) = 1e-14 * M.diagonal().maxCoeff();
    CHECK_FALSE(solver.factor(singular));
    Matrix nan = M;
    nan(n - 1, 0) = nan(0, n - 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(solver.factor(nan));
    // Refusal leaves the solver usable.
    REQUIRE(solver.factor(M));
  }
}
