#include <cmath>

#include <symdyn/runtime/spd_solver.hpp>
#include <symdyn/runtime/tree_solver.hpp>

namespace symdyn::runtime {

TreeSolver::TreeSolver(int n)
    : L_(Matrix::Zero(n, n)), parent_(static_cast<std::size_t>(n), -1), depth_(parent_) {}

// The elimination tree of M with its last coordinate eliminated first (Liu's
// algorithm, CSparse's cs_etree in reverse order): for each nonzero M_jk,
// j > k, k becomes the root above j's subtree; `ancestor` compresses the paths.
// Column-major: entry (j, k) at [j + k·n], column k below its diagonal contiguous.
bool TreeSolver::read_tree(const Matrix& M) {
  const int n = size();
  const double* m = M.data();
  // Every nonzero of M is on the tree's paths: too many refuse M at once (a chain's).
  const double budget = kDenseShare * 0.5 * n * (n - 1);
  int nonzeros = 0;
  for (int k = 0; k < n; ++k) {
    for (int j = k + 1; j < n; ++j) nonzeros += m[j + k * n] != 0.0;
  }
  if (nonzeros > budget) return false;
  std::vector<int>& ancestor = depth_;  // reused: depths are counted after
  for (int k = n - 1; k >= 0; --k) {
    parent_[static_cast<std::size_t>(k)] = -1;
    ancestor[static_cast<std::size_t>(k)] = -1;
    for (int j = k + 1; j < n; ++j) {
      if (m[j + k * n] == 0.0) continue;
      int r = j;
      while (ancestor[static_cast<std::size_t>(r)] >= 0 &&
             ancestor[static_cast<std::size_t>(r)] != k) {
        const int next = ancestor[static_cast<std::size_t>(r)];
        ancestor[static_cast<std::size_t>(r)] = k;
        r = next;
      }
      if (ancestor[static_cast<std::size_t>(r)] < 0) {
        ancestor[static_cast<std::size_t>(r)] = k;
        parent_[static_cast<std::size_t>(r)] = k;
      }
    }
  }
  off_diagonal_ = 0;
  for (int i = 0; i < n; ++i) {  // parents come first
    const int p = parent_[static_cast<std::size_t>(i)];
    depth_[static_cast<std::size_t>(i)] = p < 0 ? 0 : depth_[static_cast<std::size_t>(p)] + 1;
    off_diagonal_ += depth_[static_cast<std::size_t>(i)];
  }
  return off_diagonal_ <= budget;
}

// Leaves first (Featherstone's LTL): L_kk = sqrt(M_kk), L_ki = M_ki / L_kk for
// the ancestors i of k, then M_ij -= L_ki·L_kj for the ancestors i of k and j of
// i (with i itself): the ancestors' rows are all that elimination touches.
bool TreeSolver::factor(const Matrix& M) {
  if (size() <= kDenseUpTo || M.rows() != size() || M.cols() != size() || !read_tree(M))
    return false;
  const int n = size();
  const double* m = M.data();
  double* l = L_.data();
  const auto ancestors = [&](int i, auto&& f) {
    for (int a = parent_[static_cast<std::size_t>(i)]; a >= 0;
         a = parent_[static_cast<std::size_t>(a)])
      f(a);
  };
  for (int i = 0; i < n; ++i) {
    l[i + i * n] = m[i + i * n];
    ancestors(i, [&](int a) { l[i + a * n] = m[i + a * n]; });
  }
  for (int k = n - 1; k >= 0; --k) {
    const double d = l[k + k * n];
    if (!(d > 0.0) || d <= SpdSolver::kSingularRatio * m[k + k * n]) return false;  // also NaN
    const double Lkk = std::sqrt(d);
    l[k + k * n] = Lkk;
    ancestors(k, [&](int i) { l[k + i * n] /= Lkk; });
    ancestors(k, [&](int i) {
      const double c = l[k + i * n];
      l[i + i * n] -= c * c;
      ancestors(i, [&](int j) { l[i + j * n] -= c * l[k + j * n]; });
    });
  }
  return true;
}

void TreeSolver::solve_in_place(Matrix& B) {
  solve<false>(B, B);
}

void TreeSolver::solve_negated_in_place(Matrix& B) {
  solve<true>(B, B);
}

void TreeSolver::solve_negated(const RowMajorMatrix& B, Matrix& X) {
  solve<true>(B, X);
}

// Lᵀ·Y = B leaves first, then L·X = Y root first, on B's rows (contiguous in
// rows_, so that each row operation is a vectorized loop across the columns).
template <bool negate, class RightHandSides>
void TreeSolver::solve(const RightHandSides& B, Matrix& X) {
  const int n = size();
  const Eigen::Index m = B.cols();
  rows_ = B;
  const double* l = L_.data();
  double* r = rows_.data();
  const auto row = [&](int i) { return r + i * m; };
  const auto axpy = [&](int i, int k, double c) {  // row i -= c·row k
    double* ri = row(i);
    const double* rk = row(k);
    for (Eigen::Index j = 0; j < m; ++j) ri[j] -= c * rk[j];
  };
  const auto scale = [&](int i, double c) {
    double* ri = row(i);
    for (Eigen::Index j = 0; j < m; ++j) ri[j] *= c;
  };
  for (int k = n - 1; k >= 0; --k) {
    scale(k, 1.0 / l[k + k * n]);
    for (int a = parent_[static_cast<std::size_t>(k)]; a >= 0;
         a = parent_[static_cast<std::size_t>(a)])
      axpy(a, k, l[k + a * n]);
  }
  for (int k = 0; k < n; ++k) {
    for (int a = parent_[static_cast<std::size_t>(k)]; a >= 0;
         a = parent_[static_cast<std::size_t>(a)])
      axpy(k, a, l[k + a * n]);
    scale(k, 1.0 / l[k + k * n]);
  }
  if constexpr (negate) {
    X = -rows_;
  } else {
    X = rows_;
  }
}

}  // namespace symdyn::runtime
