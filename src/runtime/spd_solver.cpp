#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <symdyn/runtime/detail/dense_kernels.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace symdyn::runtime {

namespace {

const detail::DenseKernels* chosen_kernels(SpdSolver::Kernels kernels) {
  const detail::DenseKernels* wide = detail::wide_dense_kernels();
  switch (kernels) {
    case SpdSolver::Kernels::plain:
      return &detail::plain_dense_kernels();
    case SpdSolver::Kernels::wide:
      if (wide == nullptr) {
        throw std::invalid_argument(
            "SpdSolver: the wide kernels (AVX2 with FMA) are not built or not run by this "
            "processor (SpdSolver::wide_kernels_available())");
      }
      return wide;
    case SpdSolver::Kernels::best:
      break;
  }
  return wide != nullptr ? wide : &detail::plain_dense_kernels();
}

}  // namespace

bool SpdSolver::wide_kernels_available() {
  return detail::wide_dense_kernels() != nullptr;
}

const char* SpdSolver::kernels_name() const {
  return kernels_->name;
}

SpdSolver::SpdSolver(int n, Kernels kernels)
    : L_(Matrix::Identity(n, n)),
      kernels_(chosen_kernels(kernels)),
      tile_(static_cast<std::size_t>(n) * detail::kWidestTile) {}

// Both ways compute L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj with the same
// operations in the same order, so the factor is the same to the bit whichever
// runs: the column loop below on a few coordinates, the kernels' (vectorized
// across rows, detail/dense_kernels.hpp) above, where it is up to twice faster.
bool SpdSolver::factor(const Matrix& M) {
  if (M.rows() != size() || M.cols() != size()) return false;
  const bool positive = size() <= kFactorLoopUpTo
                            ? factor_by_columns(M)
                            : kernels_->factor(size(), M.data(), L_.data(), &smallest_ratio_);
  return positive && smallest_ratio_ > kSingularRatio;
}

// L_jj = sqrt(M_jj - Σ_k<j L_jk²),  L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj  (i > j)
// Column-major: entry (i, j) at [i + j·n]. (Vectorized down the columns it is
// up to twice slower on a few coordinates, its loops too short.)
bool SpdSolver::factor_by_columns(const Matrix& M) {
  const Eigen::Index n = L_.rows();
  const double* m = M.data();
  double* l = L_.data();
  double smallest = 1.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = m[j + j * n];
    for (Eigen::Index k = 0; k < j; ++k) d -= l[j + k * n] * l[j + k * n];
    if (!(d > 0.0)) {  // also NaN
      smallest_ratio_ = d < 0.0 && m[j + j * n] > 0.0 ? d / m[j + j * n] : 0.0;
      return false;
    }
    smallest = std::min(smallest, d / m[j + j * n]);
    const double Ljj = std::sqrt(d);
    l[j + j * n] = Ljj;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = m[i + j * n];
      for (Eigen::Index k = 0; k < j; ++k) sum -= l[i + k * n] * l[j + k * n];
      l[i + j * n] = sum / Ljj;
    }
  }
  smallest_ratio_ = smallest;
  return true;
}

// L·y = b forward, then Lᵀ·x = y backward.
void SpdSolver::solve_in_place(Vector& b) const {
  solve<false>(b.data(), b);
}

void SpdSolver::solve_negated(const Vector& b, Vector& x) const {
  solve<true>(b.data(), x);
}

// x := ±M⁻¹·b; b may be x's own storage.
template <bool negate>
[[gnu::always_inline]] inline void SpdSolver::solve(const double* b, Vector& out) const {
  const Eigen::Index n = L_.rows();
  if (n > kLoopUpTo) {
    if constexpr (negate) {
      out = -Eigen::Map<const Vector>(b, n);
    } else if (b != out.data()) {
      out = Eigen::Map<const Vector>(b, n);
    }
    const auto L = L_.triangularView<Eigen::Lower>();
    L.solveInPlace(out);
    L.adjoint().solveInPlace(out);
    return;
  }
  substitute<negate>(b, out.data());
}

template <bool negate>
[[gnu::always_inline]] inline void SpdSolver::substitute(const double* b, double* x) const {
  const Eigen::Index n = L_.rows();
  const double* l = L_.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    double sum = negate ? -b[i] : b[i];
    for (Eigen::Index k = 0; k < i; ++k) sum -= l[i + k * n] * x[k];
    x[i] = sum / l[i + i * n];
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    double sum = x[i];
    for (Eigen::Index k = i + 1; k < n; ++k) sum -= l[k + i * n] * x[k];
    x[i] = sum / l[i + i * n];
  }
}

void SpdSolver::solve_in_place(Matrix& B) {
  solve_matrix<false>(B);
}

void SpdSolver::solve_negated_in_place(Matrix& B) {
  solve_matrix<true>(B);
}

template <bool negate>
void SpdSolver::solve_matrix(Matrix& B) {
  const int n = size(), m = static_cast<int>(B.cols());
  if (n <= kInPlaceUpTo) {
    solve_rows_in_place<negate>(B);
    return;
  }
  kernels_->solve(n, L_.data(), {B.data(), 1, n, B.data(), m}, negate, tile_.data());
}

void SpdSolver::solve_negated(const RowMajorMatrix& B, Matrix& X) {
  const int n = size(), m = static_cast<int>(B.cols());
  X.resize(n, m);
  if (n <= kInPlaceUpTo) {
    X = B;
    solve_rows_in_place<true>(X);
    return;
  }
  kernels_->solve(n, L_.data(), {B.data(), m, 1, X.data(), m}, true, tile_.data());
}

// Row by row, every column at once: B_i := (±B_i - Σ_k<i L_ik·B_k) / L_ii,
// then B_i := (B_i - Σ_k>i L_ki·B_k) / L_ii backward; the multiply-adds of a
// row are independent across the columns (column by column they are a chain).
template <bool negate>
void SpdSolver::solve_rows_in_place(Matrix& B) const {
  const Eigen::Index n = L_.rows(), m = B.cols();
  const double* l = L_.data();
  double* b = B.data();
  const auto axpy = [&](Eigen::Index i, Eigen::Index k, double c) {
    for (Eigen::Index j = 0; j < m; ++j) b[i + j * n] -= c * b[k + j * n];
  };
  const auto scale = [&](Eigen::Index i, double c) {
    for (Eigen::Index j = 0; j < m; ++j) b[i + j * n] *= c;
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    if constexpr (negate) scale(i, -1.0);
    for (Eigen::Index k = 0; k < i; ++k) axpy(i, k, l[i + k * n]);
    scale(i, 1.0 / l[i + i * n]);
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    for (Eigen::Index k = i + 1; k < n; ++k) axpy(i, k, l[k + i * n]);
    scale(i, 1.0 / l[i + i * n]);
  }
}

namespace {

// The components of a unit vector u that make up 99 % of it, largest first
// (ties in index order).
std::vector<int> main_components(const Vector& u) {
  std::vector<int> order(static_cast<std::size_t>(u.size()));
  for (int j = 0; j < u.size(); ++j) order[static_cast<std::size_t>(j)] = j;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return std::abs(u(a)) > std::abs(u(b)); });
  std::vector<int> main;
  double covered = 0.0;
  for (int j : order) {
    main.push_back(j);
    covered += u(j) * u(j);
    if (covered >= 0.99 * u.squaredNorm()) break;
  }
  return main;
}

// "'a' (0.71), 'b' (-0.71)", signed so that the largest component is positive
// (a direction's sign is arbitrary).
std::string components(const Vector& u, const std::vector<int>& main, const std::vector<int>& shown,
                       const std::function<std::string(int)>& name) {
  const double sign = u(main.front()) < 0.0 ? -1.0 : 1.0;
  std::vector<std::string> parts;
  for (int j : shown) parts.push_back(fmt::format("'{}' ({:.2f})", name(j), sign * u(j)));
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace

std::string null_direction(const Matrix& A, const std::function<std::string(int)>& name) {
  if (A.rows() == 0 || !A.allFinite()) return "(a matrix that is not finite)";
  const Eigen::JacobiSVD<Matrix> svd(A, Eigen::ComputeFullV);
  const Vector u = svd.matrixV().col(A.cols() - 1);  // singular values in decreasing order
  const std::vector<int> main = main_components(u);
  return main.size() == 1 ? fmt::format("'{}'", name(main[0])) : components(u, main, main, name);
}

std::string mass_matrix_singularity(const Matrix& M, const std::function<std::string(int)>& name) {
  if (M.rows() == 0 || !M.allFinite()) return "it is not finite";
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(M);
  const Vector u = eig.eigenvectors().col(0);  // eigenvalues in increasing order
  const std::vector<int> main = main_components(u);
  if (eig.eigenvalues()(0) < -SpdSolver::kSingularRatio * eig.eigenvalues().cwiseAbs().maxCoeff()) {
    return fmt::format("it is indefinite along {}", components(u, main, main, name));
  }
  if (main.size() == 1) return fmt::format("coordinate '{}' moves no mass", name(main[0]));
  const std::vector<int> last(main.end() - 1, main.end());
  const std::vector<int> rest(main.begin(), main.end() - 1);
  return fmt::format("coordinates {} and {} move the bodies the same way",
                     components(u, main, rest, name), components(u, main, last, name));
}

}  // namespace symdyn::runtime
