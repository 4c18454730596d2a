// LuSolver against Eigen's FullPivLU, on both sides of its switch to Eigen's
// PartialPivLU, with pivoting needed, and what it refuses.

#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include <symdyn/runtime/detail/lu_solver.hpp>

using namespace symdyn::runtime;

TEST_CASE("LuSolver solves as Eigen's LU does, below and above its switch", "[runtime][solver]") {
  for (int n : {1, 2, 3, 5, 13, LuSolver::kLoopUpTo, LuSolver::kLoopUpTo + 1, 64}) {
    CAPTURE(n);
    // Random and non-symmetric, with a small diagonal: every column needs a row swap.
    Matrix A = Matrix::Random(n, n);
    A.diagonal() *= 1e-3;
    const Vector b = Vector::Random(n);
    LuSolver solver(n);
    REQUIRE(solver.factor(A));
    Vector x(n);
    solver.solve(b, x);
    const Vector expected = A.fullPivLu().solve(b);
    CHECK((x - expected).norm() <= 1e-10 * expected.norm());
    CHECK((A * x - b).norm() <= 1e-12 * (A.norm() * x.norm() + b.norm()));
    // In place: b and x the same vector.
    Vector y = b;
    solver.solve(y, y);
    CHECK(y == x);
  }
}

TEST_CASE("LuSolver refuses a singular matrix or a NaN, and factors again after",
          "[runtime][solver]") {
  for (int n : {3, LuSolver::kLoopUpTo + 1}) {
    CAPTURE(n);
    LuSolver solver(n);
    Matrix A = Matrix::Random(n, n);
    // Rank n - 1 exactly: a zero column stays zero through the elimination, so its pivot is
    // 0 whatever the random values (a column twice another leaves a pivot of rounding).
    A.col(1).setZero();
    CHECK_FALSE(solver.factor(A));
    A(0, 0) = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(solver.factor(A));
    CHECK_FALSE(solver.factor(Matrix::Zero(n, n)));
    const Matrix B = Matrix::Identity(n, n) * 4.0;
    REQUIRE(solver.factor(B));
    Vector x(n);
    solver.solve(Vector::Ones(n), x);
    CHECK(x == Vector::Constant(n, 0.25));
  }
}
