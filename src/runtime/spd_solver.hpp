#pragma once
// Solves M·x = b for the symmetric positive definite mass matrix, factored as
// M = L·Lᵀ (Cholesky) in storage sized once: nothing allocates after
// construction, so it serves the integrators' step loop.
//
// Why two factorizations: for the few coordinates of most models a plain
// column loop is several times cheaper than Eigen's dynamic-size LLT (which
// pays for its generality at every column), while from about 40 coordinates
// Eigen's blocked, vectorized LLT is faster (bench/results/runtime_overhead.md).
//
// M is refused when it is not positive definite, or when its smallest
// pivot of L·D·Lᵀ (D_k = L_kk²) is below 1e-12 of its largest: a
// coordinate without inertia, or a configuration where two coordinates move
// the same way (a gimbal lock).

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "runtime/dynamic_system.hpp"

namespace symdyn::runtime {

class SpdSolver {
 public:
  explicit SpdSolver(int n = 0);

  int size() const { return static_cast<int>(L_.rows()); }

  // Factors M (n x n; only its lower triangle is read). False when M is
  // refused (see above): then solve_in_place must not be called.
  bool factor(const Matrix& M);

  // b := M⁻¹·b (n).
  void solve_in_place(Vector& b) const;

  // Smallest and largest pivot D_k = L_kk² of the last factorization; the
  // smallest is the first non-positive one when M is not positive definite.
  double smallest_pivot() const { return smallest_; }
  double largest_pivot() const { return largest_; }

  // Pivots below this fraction of the largest mean M is singular.
  static constexpr double kSingularRatio = 1e-12;
  // Up to this size the column loop, above it Eigen's LLT.
  static constexpr int kLoopUpTo = 40;

 private:
  bool factor_by_columns(const Matrix& M);
  bool factor_blocked(const Matrix& M);

  Matrix L_;  // (n x n) its lower triangle is L
  double smallest_ = 0.0;
  double largest_ = 0.0;
};

}  // namespace symdyn::runtime
