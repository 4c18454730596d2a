#include <cmath>
#include <utility>

#include <symdyn/runtime/detail/lu_solver.hpp>

namespace symdyn::runtime {

LuSolver::LuSolver(int n) : lu_(Matrix::Zero(n, n)), pivot_(Eigen::VectorXi::Zero(n)), big_(n) {}

// Doolittle by columns with row swaps (column-major: entry (i, j) at [i + j·n]): for
// k = 0 .. n-1, the largest |a_ik| (i >= k) is swapped to row k, then
// l_ik = a_ik / a_kk and a_ij -= l_ik·a_kj for i, j > k.
bool LuSolver::factor(const Matrix& A) {
  const Eigen::Index n = lu_.rows();
  if (n > kLoopUpTo) {
    big_.compute(A);
    // Eigen's LU never fails: a zero or non-finite pivot shows on U's diagonal.
    const auto u = big_.matrixLU().diagonal();
    return u.allFinite() && (u.array() != 0.0).all();
  }
  lu_ = A;
  double* a = lu_.data();
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index p = k;
    double largest = std::abs(a[k + k * n]);
    for (Eigen::Index i = k + 1; i < n; ++i) {
      const double v = std::abs(a[i + k * n]);
      if (v > largest) {
        largest = v;
        p = i;
      }
    }
    if (!(largest > 0.0) || !std::isfinite(largest)) return false;  // also NaN
    pivot_[k] = static_cast<int>(p);
    if (p != k) {
      for (Eigen::Index j = 0; j < n; ++j) std::swap(a[k + j * n], a[p + j * n]);
    }
    const double inverse = 1.0 / a[k + k * n];
    for (Eigen::Index i = k + 1; i < n; ++i) a[i + k * n] *= inverse;
    for (Eigen::Index j = k + 1; j < n; ++j) {
      const double akj = a[k + j * n];
      if (akj == 0.0) continue;
      for (Eigen::Index i = k + 1; i < n; ++i) a[i + j * n] -= a[i + k * n] * akj;
    }
  }
  return true;
}

// P·b, then L·y = P·b forward, then U·x = y backward.
void LuSolver::solve(const Vector& b, Vector& x) const {
  const Eigen::Index n = lu_.rows();
  if (n > kLoopUpTo) {
    x = big_.solve(b);
    return;
  }
  if (x.data() != b.data()) x = b;
  double* v = x.data();
  const double* a = lu_.data();
  for (Eigen::Index k = 0; k < n; ++k) {
    if (pivot_[k] != k) std::swap(v[k], v[pivot_[k]]);
  }
  for (Eigen::Index j = 0; j < n; ++j) {
    const double vj = v[j];
    if (vj == 0.0) continue;
    for (Eigen::Index i = j + 1; i < n; ++i) v[i] -= a[i + j * n] * vj;
  }
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    v[j] /= a[j + j * n];
    const double vj = v[j];
    if (vj == 0.0) continue;
    for (Eigen::Index i = 0; i < j; ++i) v[i] -= a[i + j * n] * vj;
  }
}

}  // namespace symdyn::runtime
