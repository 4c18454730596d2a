// SpdSolver against Eigen's LLT, on both sides of its switches (the factor's
// plain column loop to its kernels', the single solves' loop to Eigen's), with
// its plain kernels and its wide ones (AVX2 with FMA, where this processor runs
// them), its factor against the textbook column loop to the bit, and what it
// refuses.

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <symdyn/runtime/spd_solver.hpp>

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

// The kernels this build and processor can run: plain always, wide maybe.
std::vector<SpdSolver::Kernels> runnable_kernels() {
  if (SpdSolver::wide_kernels_available())
    return {SpdSolver::Kernels::plain, SpdSolver::Kernels::wide};
  WARN("no AVX2 with FMA here: the wide kernels are not tested");
  return {SpdSolver::Kernels::plain};
}

// The textbook Cholesky column loop, L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj,
// sums in increasing k, the diagonal L_jj = sqrt(M_jj - Σ_k<j L_jk²).
Matrix textbook_cholesky(const Matrix& M) {
  const Eigen::Index n = M.rows();
  Matrix L = Matrix::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j; i < n; ++i) {
      double sum = M(i, j);
      for (Eigen::Index k = 0; k < j; ++k) sum -= L(i, k) * L(j, k);
      L(i, j) = i == j ? std::sqrt(sum) : sum / L(j, j);
    }
  }
  return L;
}

// x = L⁻ᵀ·L⁻¹·b as SpdSolver's single solve does it: its column loop up to
// kLoopUpTo coordinates (sums in increasing k), Eigen's triangular solves above.
Vector textbook_solve(const Matrix& L, const Vector& b) {
  const Eigen::Index n = L.rows();
  Vector x = b;
  if (n > SpdSolver::kLoopUpTo) {
    L.triangularView<Eigen::Lower>().solveInPlace(x);
    L.triangularView<Eigen::Lower>().adjoint().solveInPlace(x);
    return x;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double sum = b(i);
    for (Eigen::Index k = 0; k < i; ++k) sum -= L(i, k) * x(k);
    x(i) = sum / L(i, i);
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    double sum = x(i);
    for (Eigen::Index k = i + 1; k < n; ++k) sum -= L(k, i) * x(k);
    x(i) = sum / L(i, i);
  }
  return x;
}

}  // namespace

TEST_CASE("SpdSolver's factor is the textbook column loop's to the bit, in every kernel and size",
          "[runtime][solver]") {
  // The single solve reads nothing but L: the same bits out of it mean the same L.
  for (const SpdSolver::Kernels kernels : runnable_kernels()) {
    for (int n = 1; n <= 100; n += n < 24 ? 1 : 7) {
      const Matrix M = random_spd(n, 4.0);
      const Matrix L = textbook_cholesky(M);
      SpdSolver solver(n, kernels);
      CAPTURE(n, solver.kernels_name());
      REQUIRE(solver.factor(M));
      double ratio = 1.0;
      for (int j = 0; j < n; ++j) ratio = std::min(ratio, L(j, j) * L(j, j) / M(j, j));
      // D_j against L_jj² (a square root and a square apart).
      CHECK(std::abs(solver.smallest_pivot_ratio() - ratio) <= 1e-15 * ratio);
      const Vector b = Vector::Random(n);
      Vector x = b;
      solver.solve_in_place(x);
      // Sums of the same products in the same order: no tolerance.
      CHECK((x - textbook_solve(L, b)).cwiseAbs().maxCoeff() == 0.0);
    }
  }
}

TEST_CASE("SpdSolver's plain and wide kernels solve many right-hand sides as Eigen's LLT",
          "[runtime][solver]") {
  for (const SpdSolver::Kernels kernels : runnable_kernels()) {
    for (int n = 1; n <= 80; ++n) {
      const Matrix M = random_spd(n, 3.0);
      const Eigen::LLT<Matrix> llt(M);
      SpdSolver solver(n, kernels);
      CAPTURE(n, solver.kernels_name());
      REQUIRE(solver.factor(M));
      // Column counts across the tiles' widths (16, 12, 8, 4 with AVX2; 8, 6, 4, 2) and their
      // rests.
      for (int m : {1, 3, 2 * n, 2 * n + 1, 77}) {
        CAPTURE(m);
        const Matrix B = Matrix::Random(n, m);
        const Matrix reference = llt.solve(B);
        Matrix X = B, Y = B, Z;
        solver.solve_in_place(X);
        solver.solve_negated_in_place(Y);
        // B row-major, as the emitted derivatives come: the same operations, the same X.
        solver.solve_negated(RowMajorMatrix(B), Z);
        CHECK(Z == Y);
        // Condition 1e3: forward error within 1e3 times the backward one.
        CHECK((X - reference).norm() <= 1e-11 * reference.norm());
        CHECK((Y + reference).norm() <= 1e-11 * reference.norm());
        // Backward stable: a residual of a few n·ε of ‖M‖·‖X‖.
        CHECK((M * X - B).norm() <= 4.0 * n * 2.22e-16 * M.norm() * X.norm());
        CHECK((M * Y + B).norm() <= 4.0 * n * 2.22e-16 * M.norm() * Y.norm());
      }
    }
  }
}

TEST_CASE("SpdSolver's wide kernels agree with its plain ones to rounding", "[runtime][solver]") {
  CHECK(std::string_view(SpdSolver(3, SpdSolver::Kernels::plain).kernels_name()) == "plain");
  if (!SpdSolver::wide_kernels_available()) {
    CHECK_THROWS_AS(SpdSolver(3, SpdSolver::Kernels::wide), std::invalid_argument);
    CHECK(std::string_view(SpdSolver(3).kernels_name()) == "plain");
    return;
  }
  CHECK(std::string_view(SpdSolver(3).kernels_name()) == "avx2");
  for (int n : {5, 40, 64}) {
    CAPTURE(n);
    const Matrix M = random_spd(n, 2.0);
    SpdSolver plain(n, SpdSolver::Kernels::plain), wide(n, SpdSolver::Kernels::wide);
    REQUIRE(plain.factor(M));
    REQUIRE(wide.factor(M));
    CHECK(std::abs(wide.smallest_pivot_ratio() - plain.smallest_pivot_ratio()) <=
          1e-12 * plain.smallest_pivot_ratio());
    const Matrix B = Matrix::Random(n, 2 * n);
    Matrix X = B, Y = B;
    plain.solve_negated_in_place(X);
    wide.solve_negated_in_place(Y);
    CHECK((X - Y).norm() <= 1e-12 * X.norm());
  }
}

TEST_CASE("SpdSolver solves as Eigen's LLT does, below and above its switch", "[runtime][solver]") {
  for (int n : {1, 2, 3, 5, 13, SpdSolver::kFactorLoopUpTo, SpdSolver::kFactorLoopUpTo + 1, 24,
                SpdSolver::kLoopUpTo, SpdSolver::kLoopUpTo + 1, 64}) {
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
    // A pivot D_k = L_kk² of an SPD matrix is at least its smallest
    // eigenvalue (1e-3), and at most its own diagonal.
    CHECK(solver.smallest_pivot_ratio() >= 1e-3 * (1.0 - 1e-9) / M.diagonal().maxCoeff());
    CHECK(solver.smallest_pivot_ratio() <= 1.0 + 1e-12);
  }
}

TEST_CASE("SpdSolver solves several right-hand sides at once as column by column",
          "[runtime][solver]") {
  for (int n : {1, 2, 8, 9, 13, SpdSolver::kLoopUpTo + 1, 64}) {
    CAPTURE(n);
    const Matrix M = random_spd(n, 3.0);
    SpdSolver solver(n);
    REQUIRE(solver.factor(M));
    for (int m : {1, n, 2 * n + 1}) {
      CAPTURE(m);
      const Matrix B = Matrix::Random(n, m);
      Matrix X = B, Y = B;
      solver.solve_in_place(X);
      solver.solve_negated_in_place(Y);
      for (int j = 0; j < m; ++j) {
        Vector x = B.col(j);
        solver.solve_in_place(x);
        CHECK((X.col(j) - x).norm() <= 1e-12 * x.norm());
        CHECK((Y.col(j) + x).norm() <= 1e-12 * x.norm());
      }
      CHECK((M * X - B).norm() <= 1e-12 * 1e3 * B.norm());
    }
  }
}

TEST_CASE("SpdSolver refuses indefinite, singular and non-finite matrices", "[runtime][solver]") {
  for (const auto& [n, kernels] :
       {std::pair{3, SpdSolver::Kernels::plain}, std::pair{3, SpdSolver::Kernels::best},
        std::pair{SpdSolver::kFactorLoopUpTo + 5, SpdSolver::Kernels::plain},
        std::pair{SpdSolver::kLoopUpTo + 5, SpdSolver::Kernels::best}}) {
    SpdSolver solver(n, kernels);
    CAPTURE(n, solver.kernels_name());
    Matrix M = random_spd(n, 1.0);
    REQUIRE(solver.factor(M));
    Matrix indefinite = M;
    indefinite(n - 1, n - 1) = -1.0;
    CHECK_FALSE(solver.factor(indefinite));
    // A coordinate without inertia.
    Matrix massless = M;
    massless.row(1).setZero();
    massless.col(1).setZero();
    CHECK_FALSE(solver.factor(massless));
    // Two coordinates that move the same masses the same way (rank n - 1):
    // their pivot is rounding of their diagonal.
    Matrix twins = M;
    twins.row(2) = 2.0 * twins.row(0);
    twins.col(2) = 2.0 * twins.col(0);
    CHECK_FALSE(solver.factor(twins));
    CHECK(solver.smallest_pivot_ratio() <= SpdSolver::kSingularRatio);
    // A light coordinate beside heavy ones is not singular: the test is
    // against each coordinate's own diagonal.
    Matrix light = M;
    light.row(1) *= 1e-9;
    light.col(1) *= 1e-9;
    CHECK(solver.factor(light));
    Matrix nan = M;
    nan(n - 1, 0) = nan(0, n - 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(solver.factor(nan));
    // A matrix of another size.
    CHECK_FALSE(solver.factor(Matrix::Identity(n + 1, n + 1)));
    CHECK_FALSE(solver.factor(Matrix::Identity(n, n - 1)));
    // Refusal leaves the solver usable.
    REQUIRE(solver.factor(M));
  }
}

TEST_CASE("a refused mass matrix is explained in coordinate names", "[runtime][solver]") {
  const auto name = [](int j) { return fmt::format("q{}", j); };
  Matrix M = Matrix::Identity(3, 3);
  M(1, 1) = 0.0;
  CHECK(mass_matrix_singularity(M, name) == "coordinate 'q1' moves no mass");
  // q0 and q2 move the same body: M = [1 0 1; 0 1 0; 1 0 1].
  M = Matrix::Identity(3, 3);
  M(0, 2) = M(2, 0) = M(2, 2) = 1.0;
  CHECK(mass_matrix_singularity(M, name) ==
        "coordinates 'q0' (0.71) and 'q2' (-0.71) move the bodies the same way");
  M(1, 1) = -2.0;
  CHECK(mass_matrix_singularity(M, name) == "it is indefinite along 'q1' (1.00)");
  // A general square matrix: its null direction.
  Matrix A = Matrix::Identity(2, 2);
  A(1, 1) = 0.0;
  CHECK(null_direction(A, name) == "'q1'");
}
