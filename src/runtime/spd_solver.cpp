#include "runtime/spd_solver.hpp"

#include <algorithm>
#include <cmath>

namespace symdyn::runtime {

SpdSolver::SpdSolver(int n) : L_(Matrix::Identity(n, n)) {}

bool SpdSolver::factor(const Matrix& M) {
  const bool positive = size() <= kLoopUpTo ? factor_by_columns(M) : factor_blocked(M);
  return positive && smallest_ > kSingularRatio * largest_;
}

// L_jj = sqrt(M_jj - Σ_k<j L_jk²),  L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj  (i > j)
// Column-major: entry (i, j) at [i + j·n].
bool SpdSolver::factor_by_columns(const Matrix& M) {
  const Eigen::Index n = L_.rows();
  const double* m = M.data();
  double* l = L_.data();
  double smallest = 0.0, largest = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = m[j + j * n];
    for (Eigen::Index k = 0; k < j; ++k) d -= l[j + k * n] * l[j + k * n];
    if (!(d > 0.0)) {  // also NaN
      smallest_ = d;
      largest_ = largest;
      return false;
    }
    smallest = j == 0 ? d : std::min(smallest, d);
    largest = std::max(largest, d);
    const double Ljj = std::sqrt(d);
    l[j + j * n] = Ljj;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = m[i + j * n];
      for (Eigen::Index k = 0; k < j; ++k) sum -= l[i + k * n] * l[j + k * n];
      l[i + j * n] = sum / Ljj;
    }
  }
  smallest_ = smallest;
  largest_ = largest;
  return true;
}

bool SpdSolver::factor_blocked(const Matrix& M) {
  L_ = M;
  const Eigen::LLT<Eigen::Ref<Matrix>> llt(L_);  // factors L_ in place
  // Eigen's pivot test (x <= 0) lets NaN through.
  if (llt.info() != Eigen::Success || !L_.diagonal().allFinite()) {
    smallest_ = largest_ = 0.0;
    return false;
  }
  smallest_ = L_.diagonal().cwiseAbs2().minCoeff();
  largest_ = L_.diagonal().cwiseAbs2().maxCoeff();
  return true;
}

// L·y = b forward, then Lᵀ·x = y backward.
void SpdSolver::solve_in_place(Vector& b) const {
  const Eigen::Index n = L_.rows();
  if (n > kLoopUpTo) {
    const auto L = L_.triangularView<Eigen::Lower>();
    L.solveInPlace(b);
    L.adjoint().solveInPlace(b);
    return;
  }
  const double* l = L_.data();
  double* x = b.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    double sum = x[i];
    for (Eigen::Index k = 0; k < i; ++k) sum -= l[i + k * n] * x[k];
    x[i] = sum / l[i + i * n];
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    double sum = x[i];
    for (Eigen::Index k = i + 1; k < n; ++k) sum -= l[k + i * n] * x[k];
    x[i] = sum / l[i + i * n];
  }
}

}  // namespace symdyn::runtime
