#pragma once
// Solves M·X = B for a mass matrix with the sparsity of a tree, factored as
// M = Lᵀ·L with its leaves eliminated first (Featherstone's LTL, Rigid Body
// Dynamics Algorithms §6.5; MuJoCo's mj_factorM): no fill-in off the tree's
// paths to its root, and the work is Σ_i depth(i) per column where a dense
// solve's is n²/2.
//
// The tree is read from M itself at each factorization: its elimination tree
// (coordinate i's parent λ(i) < i; Liu's algorithm), on whose paths to the root
// every nonzero of M and of L lies. So the factorization is exact for the M at
// hand whatever the model (a coupling of two branches merges them), and M is
// refused, for the caller to solve dense (SpdSolver), when its tree has too
// few zeros to pay.
//
// A pivot D_k = L_kk² is what coordinate k's inertia has left once its
// descendants are eliminated; below SpdSolver::kSingularRatio of M_kk the
// factorization is refused too, so that SpdSolver decides and names why.
// Storage is sized once at construction and at the first solve of each width.

#include <Eigen/Core>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

class TreeSolver {
 public:
  explicit TreeSolver(int n = 0);

  int size() const { return static_cast<int>(L_.rows()); }

  // Factors M (n x n, only its lower triangle read) when n > kDenseUpTo, its
  // tree leaves at most kDenseShare of the dense triangle's entries below the
  // diagonal, and its pivots pass (see above). False otherwise: then no solve.
  bool factor(const Matrix& M);

  // B := M⁻¹·B and B := -M⁻¹·B (n x m), every column at once.
  void solve_in_place(Matrix& B);
  void solve_negated_in_place(Matrix& B);
  // X := -M⁻¹·B for B row-major, as the emitted code writes the derivatives
  // (the rows this solve works in).
  void solve_negated(const RowMajorMatrix& B, Matrix& X);

  // The parent of coordinate i in the last tree read from M (-1: a root).
  int parent(int i) const { return parent_[static_cast<std::size_t>(i)]; }
  // Entries of L below the diagonal: Σ_i depth(i) of the last tree.
  int off_diagonal_entries() const { return off_diagonal_; }

  // Sparse enough to pay: a solve costs Σ depth(i) row operations where the
  // dense one costs n(n-1)/2, but its loops follow parent links where the
  // dense kernels are blocked and vectorized: it must save a fifth of them.
  static constexpr double kDenseShare = 0.8;
  // Up to this size SpdSolver's row loop over the whole matrix is the faster.
  static constexpr int kDenseUpTo = 8;

 private:
  bool read_tree(const Matrix& M);
  template <bool negate, class RightHandSides>
  void solve(const RightHandSides& B, Matrix& X);

  Matrix L_;                 // (n x n) its lower triangle is L on the tree's pattern
  std::vector<int> parent_;  // (n) λ(i)
  std::vector<int> depth_;   // (n) the number of ancestors of i
  int off_diagonal_ = 0;     // Σ_i depth(i)
  RowMajorMatrix rows_;      // B's rows
};

}  // namespace symdyn::runtime
