#pragma once
// Solves A·x = b for a general square matrix, factored as P·A = L·U (partial pivoting)
// in storage sized once: nothing allocates after construction, so it serves the
// implicit integrators' Newton iterations (newmark.cpp), which refactor their iteration
// matrix whenever the step changes.
//
// Why two factorizations: for the few coordinates of most models a plain loop is
// several times cheaper than Eigen's dynamic-size PartialPivLU, whose factorization
// and triangular solves are blocked for large matrices and pay for it at every call
// on small ones (as SpdSolver, spd_solver.hpp); from about 40 unknowns Eigen's is faster.
//
// A is refused when a pivot is zero or not finite (A singular, or a NaN in it).

#include <Eigen/Core>
#include <Eigen/LU>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

class LuSolver {
 public:
  explicit LuSolver(int n = 0);

  int size() const { return static_cast<int>(lu_.rows()); }

  // Factors A (n x n). False when A is refused (see above): then solve must not be called.
  bool factor(const Matrix& A);

  // x := A⁻¹·b (n each, x sized); b may be x itself.
  void solve(const Vector& b, Vector& x) const;

  // Up to this size the plain loops, above it Eigen's PartialPivLU.
  static constexpr int kLoopUpTo = 40;

 private:
  Matrix lu_;              // (n x n) L below the diagonal (unit diagonal), U on and above
  Eigen::VectorXi pivot_;  // (n) row k of U came from row pivot_[k] of A, as swaps in order
  Eigen::PartialPivLU<Matrix> big_;  // above kLoopUpTo
};

}  // namespace symdyn::runtime
