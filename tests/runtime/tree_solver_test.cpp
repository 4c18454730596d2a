// TreeSolver against Eigen's dense LLT: on random SPD matrices of random trees
// (M = Lᵀ·L with L on the tree's pattern), with a coupling between two
// branches, on the trike's mass matrix at random states, and what it refuses
// (too few zeros, a matrix that is not positive definite).

#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <limits>
#include <random>
#include <vector>

#include "trike.hpp"
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/tree_solver.hpp>

using namespace symdyn::runtime;

namespace {

// Coordinate i's parent drawn in [i - span, i - 1] (-1: a root), span 1: a chain.
std::vector<int> random_tree(int n, int span, std::mt19937& rng) {
  std::vector<int> parent(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    std::uniform_int_distribution<int> pick(std::max(-1, i - span), i - 1);
    parent[static_cast<std::size_t>(i)] = i == 0 ? -1 : pick(rng);
  }
  return parent;
}

// Lᵀ·L, L lower triangular with its diagonal in [1, 2] and an entry in [-1, 1]
// at (i, a) for every ancestor a of i: exactly the tree's pattern.
Matrix tree_spd(const std::vector<int>& parent, std::mt19937& rng) {
  const int n = static_cast<int>(parent.size());
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Matrix L = Matrix::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    L(i, i) = 1.5 + 0.5 * entry(rng);
    for (int a = parent[static_cast<std::size_t>(i)]; a >= 0;
         a = parent[static_cast<std::size_t>(a)])
      L(i, a) = entry(rng);
  }
  return L.transpose() * L;
}

// X = M⁻¹·B by Eigen's dense LLT, checked against the solver's, plain and negated (B
// column-major and row-major).
void check_solves(TreeSolver& solver, const Matrix& M, std::mt19937& rng) {
  const int n = static_cast<int>(M.rows());
  const Eigen::LLT<Matrix> llt(M);
  for (int m : {1, n, 2 * n + 1}) {
    CAPTURE(m);
    std::uniform_real_distribution<double> entry(-1.0, 1.0);
    const Matrix B = Matrix::NullaryExpr(n, m, [&]() { return entry(rng); });
    const Matrix reference = llt.solve(B);
    Matrix X = B;
    solver.solve_in_place(X);
    CHECK((X - reference).norm() <= 1e-11 * reference.norm());
    X = B;
    solver.solve_negated_in_place(X);
    CHECK((X + reference).norm() <= 1e-11 * reference.norm());
    // B row-major, as the emitted derivatives come: the same operations, the same X.
    Matrix Y;
    solver.solve_negated(RowMajorMatrix(B), Y);
    CHECK(Y == X);
  }
}

}  // namespace

TEST_CASE("TreeSolver reads the tree from M and solves as Eigen's dense LLT", "[runtime][solver]") {
  std::mt19937 rng(2013);
  for (int n : {TreeSolver::kDenseUpTo + 1, 13, 24, 64}) {
    for (int span : {2, 4, n}) {
      CAPTURE(n, span);
      const std::vector<int> parent = random_tree(n, span, rng);
      const Matrix M = tree_spd(parent, rng);
      int entries = 0;
      for (int i = 0; i < n; ++i) {
        for (int a = parent[static_cast<std::size_t>(i)]; a >= 0;
             a = parent[static_cast<std::size_t>(a)])
          ++entries;
      }
      TreeSolver solver(n);
      if (entries > TreeSolver::kDenseShare * 0.5 * n * (n - 1)) {
        CHECK_FALSE(solver.factor(M));  // too few zeros to pay
        continue;
      }
      REQUIRE(solver.factor(M));
      CHECK(solver.off_diagonal_entries() == entries);
      for (int i = 0; i < n; ++i) CHECK(solver.parent(i) == parent[static_cast<std::size_t>(i)]);
      check_solves(solver, M, rng);
    }
  }
}

TEST_CASE("TreeSolver merges coupled branches, refuses a dense M, an indefinite one, a small one",
          "[runtime][solver]") {
  std::mt19937 rng(7);
  // Two legs on a root: 0 <- 1 <- 2 <- 3 <- 4 <- 5 and 0 <- 6 <- 7 <- 8 <- 9 <- 10.
  const std::vector<int> legs{-1, 0, 1, 2, 3, 4, 0, 6, 7, 8, 9};
  const Matrix M = tree_spd(legs, rng);
  TreeSolver solver(11);
  REQUIRE(solver.factor(M));
  CHECK(solver.parent(6) == 0);
  CHECK(solver.off_diagonal_entries() == 30);
  check_solves(solver, M, rng);
  // A coupling between the legs (1 and 10): elimination would fill (6, 1), so
  // the tree hangs the second leg from the first one's coordinate 1.
  Matrix coupled = M;
  coupled(10, 1) = coupled(1, 10) = 0.1;
  REQUIRE(solver.factor(coupled));
  CHECK(solver.parent(6) == 1);
  CHECK(solver.parent(10) == 9);
  CHECK(solver.off_diagonal_entries() == 35);
  check_solves(solver, coupled, rng);
  // Dense: a chain, no zero to use.
  CHECK_FALSE(solver.factor(tree_spd({-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, rng)));
  // Not positive definite, and a NaN.
  Matrix indefinite = M;
  indefinite(3, 3) = -1.0;
  CHECK_FALSE(solver.factor(indefinite));
  Matrix nan = M;
  nan(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(solver.factor(nan));
  // The wrong size, and a tree small enough for the dense row loop.
  CHECK_FALSE(TreeSolver(10).factor(M));
  CHECK_FALSE(TreeSolver(5).factor(tree_spd({-1, 0, 1, 0, 3}, rng)));
}

TEST_CASE("TreeSolver on the trike's mass matrix at random states", "[runtime][solver]") {
  MultibodySystem sys(Model::from<symdyn_generated::trike>());
  const int n = sys.num_coordinates();
  std::mt19937 rng(2013);
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  TreeSolver solver(n);
  for (int trial = 0; trial < 8; ++trial) {
    CAPTURE(trial);
    State s = sys.initial_state();
    for (int j = 0; j < n; ++j) s.q[j] += 0.5 * offset(rng);
    Matrix M;
    sys.mass_matrix(s, M);
    // The chassis' six coordinates and the wheels and suspensions on it: a tree.
    REQUIRE(solver.factor(M));
    CHECK(solver.off_diagonal_entries() < n * (n - 1) / 2);
    check_solves(solver, M, rng);
  }
}
