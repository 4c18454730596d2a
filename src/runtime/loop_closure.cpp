#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/loop_closure.hpp>

namespace symdyn::runtime {

namespace {

// A permutation's parity (+-1): each cycle of even length is an odd number of swaps.
int permutation_parity(const std::vector<int>& order) {
  std::vector<bool> seen(order.size(), false);
  int parity = 1;
  for (std::size_t k = 0; k < order.size(); ++k) {
    int length = 0;
    for (std::size_t j = k; !seen[j]; j = static_cast<std::size_t>(order[j])) {
      seen[j] = true;
      ++length;
    }
    if (length > 0 && length % 2 == 0) parity = -parity;
  }
  return parity;
}

// The columns of A (n x n, row-major) with fewest nonzeros first (stable).
std::vector<int> columns_by_sparsity(const double* A, int n) {
  std::vector<int> nonzeros(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n * n; ++i) nonzeros[static_cast<std::size_t>(i % n)] += A[i] != 0.0;
  std::vector<int> column(static_cast<std::size_t>(n));
  std::iota(column.begin(), column.end(), 0);
  std::stable_sort(column.begin(), column.end(), [&](int a, int b) {
    return nonzeros[static_cast<std::size_t>(a)] < nonzeros[static_cast<std::size_t>(b)];
  });
  return column;
}

}  // namespace

LoopClosure::LoopClosure(const Model& model)
    : n_(model.nindependent()),
      m_(model.ncon()),
      g_(m_),
      g_t_(m_),
      gamma_(m_),
      guess_(model.initial_state().q.tail(m_)),
      step_(m_),
      dq_(n_),
      g_q_(m_, n_),
      g_p_(m_, m_),
      rates_(m_, n_ + 1),
      T_(Matrix::Zero(n_ + m_, n_)),
      c_(Vector::Zero(n_ + m_)),
      mu_(m_),
      a_x_rows_(n_ + m_, m_),
      a_xd_rows_(n_ + m_, m_),
      hessian_(n_ + m_, n_ + m_),
      aT_(m_, n_),
      HT_(n_ + m_, n_),
      dxd_dq_(Matrix::Zero(n_ + m_, n_)),
      dxdd_dq_(Matrix::Zero(n_ + m_, n_)),
      dxdd_dqd_(Matrix::Zero(n_ + m_, n_)),
      curvature_(n_, n_),
      loop_size_(model.loop_names().size()),
      equilibrated_(m_, m_) {
  T_.topRows(n_).setIdentity();
  for (int k = 0; k < m_; ++k) loop_of_.push_back(model.constraint_loop(k));
}

void SmallLu::order_columns(const double* A) {
  const int total =
      static_cast<int>(std::count_if(A, A + n_ * n_, [](double a) { return a != 0.0; }));
  sparse_ = sparse_if_it_pays_ && n_ > kDenseUpTo && total <= kSparseShare * n_ * n_;
  permuted_ = false;
  if (!sparse_) {
    column_.resize(static_cast<std::size_t>(n_));
    std::iota(column_.begin(), column_.end(), 0);
    return;
  }
  column_ = columns_by_sparsity(A, n_);
  permuted_ = !std::is_sorted(column_.begin(), column_.end());
  column_parity_ = permutation_parity(column_);
}

double SmallLu::smallest_pivot() const {
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n_; ++k) smallest = std::min(smallest, std::abs(at(k, k)));
  return smallest;
}

int SmallLu::determinant_sign() const {
  int sign = column_parity_;
  for (int k = 0; k < n_; ++k) {
    if (at(k, k) == 0.0) return 0;
    if ((swap_[static_cast<std::size_t>(k)] != k) != (at(k, k) < 0.0)) sign = -sign;
  }
  return sign;
}

void SmallLu::factor(const double* A, int n) {
  factor(A, n, Eigen::Map<const Vector>(A, n * n).cwiseAbs().maxCoeff());
}

void SmallLu::factor(const double* A, int n, double largest) {
  if (n != n_ || column_.size() != static_cast<std::size_t>(n)) {
    n_ = n;
    order_columns(A);
    const auto entries = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    lu_.resize(entries);
    lower_start_.resize(static_cast<std::size_t>(n + 1));
    upper_start_.resize(static_cast<std::size_t>(n + 1));
    below_start_.resize(static_cast<std::size_t>(n + 1));
    for (auto* list : {&gather_from_, &gather_to_, &fill_, &below_}) list->reserve(entries);
    lower_.reserve(entries);
    upper_.reserve(entries);
    pattern_.assign(entries, 0);
    structure_.resize(entries);
    swap_.resize(static_cast<std::size_t>(n));
    row_.resize(static_cast<std::size_t>(n));
    pivot_row_.resize(static_cast<std::size_t>(n));
    inverse_pivot_.resize(static_cast<std::size_t>(n));
    scheduled_ = false;
  }
  if (scheduled_ && factor_by_schedule(A, largest)) return;
  eliminate(A, largest);
  if (sparse_) schedule(A);
}

// Partial pivoting, the pivot searched over all rows below and the rows
// swapped; where sparse_, the pivot row's exact zeros skipped.
void SmallLu::eliminate(const double* A, double largest) {
  const int n = n_;
  if (!permuted_) {
    std::copy(A, A + n * n, lu_.begin());
  } else {
    for (int i = 0; i < n; ++i) {
      double* to = &at(i, 0);
      for (int k = 0; k < n; ++k) to[k] = A[i * n + column_[static_cast<std::size_t>(k)]];
    }
  }
  double smallest = largest;
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i) {
      if (std::abs(at(i, k)) > std::abs(at(p, k))) p = i;
    }
    swap_[static_cast<std::size_t>(k)] = p;
    if (p != k) {
      for (int j = 0; j < n; ++j) std::swap(at(k, j), at(p, j));
    }
    const double pivot = at(k, k);
    smallest = std::min(smallest, std::abs(pivot));
    if (pivot == 0.0) continue;  // singular: the ratio says so, solves are not to be used
    inverse_pivot_[static_cast<std::size_t>(k)] = 1.0 / pivot;
    // The rows below take multiples of the pivot row's nonzeros (all of it where dense).
    int width = 0;
    for (int j = k + 1; j < n; ++j) {
      if (!sparse_ || at(k, j) != 0.0) pivot_row_[static_cast<std::size_t>(width++)] = j;
    }
    for (int i = k + 1; i < n; ++i) {
      if (at(i, k) == 0.0) continue;  // a row of another loop
      const double l = at(i, k) *= inverse_pivot_[static_cast<std::size_t>(k)];
      for (int e = 0; e < width; ++e) {
        const int j = pivot_row_[static_cast<std::size_t>(e)];
        at(i, j) -= l * at(k, j);
      }
    }
  }
  ratio_ = largest > 0 ? smallest / largest : 0.0;
}

// The schedule of the pivots eliminate() just chose: A's pattern (the entries
// nonzero in any A factored so far: one zero at a state may not be at the
// next) in L·U's order, row k A's row row_[k], with the fill-in its
// elimination makes (structure_, symbolic); L's columns, and L's and U's rows
// over it. Where A's nonzeros stay in the pattern and the pivots stay the
// largest of their columns, factor_by_schedule() repeats the elimination over
// these lists only: the same factors as eliminate()'s.
void SmallLu::schedule(const double* A) {
  const int n = n_;
  const auto index = [n](int i, int j) { return static_cast<std::size_t>(i * n + j); };
  for (int i = 0; i < n * n; ++i) {
    if (A[i] != 0.0) pattern_[static_cast<std::size_t>(i)] = 1;
  }
  for (int k = 0; k < n; ++k) row_[static_cast<std::size_t>(k)] = k;
  for (int k = 0; k < n; ++k) {
    std::swap(row_[static_cast<std::size_t>(k)],
              row_[static_cast<std::size_t>(swap_[static_cast<std::size_t>(k)])]);
  }
  gather_from_.clear();
  gather_to_.clear();
  outside_.setZero(n * n);
  fill_.clear();
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < n; ++c) {
      const int from = row_[static_cast<std::size_t>(i)] * n + column_[static_cast<std::size_t>(c)];
      const bool in = pattern_[static_cast<std::size_t>(from)] != 0;
      structure_[index(i, c)] = in;
      if (in) {
        gather_from_.push_back(from);
        gather_to_.push_back(i * n + c);
      } else {
        outside_(from) = 1.0;
      }
    }
  }
  for (int k = 0; k < n; ++k) {
    for (int r = k + 1; r < n; ++r) {
      if (!structure_[index(r, k)]) continue;
      for (int j = k + 1; j < n; ++j) {
        if (structure_[index(k, j)] && !structure_[index(r, j)]) {
          structure_[index(r, j)] = 1;
          fill_.push_back(r * n + j);
        }
      }
    }
  }
  below_.clear();
  lower_.clear();
  upper_.clear();
  for (int k = 0; k < n; ++k) {
    below_start_[static_cast<std::size_t>(k)] = static_cast<int>(below_.size());
    lower_start_[static_cast<std::size_t>(k)] = static_cast<int>(lower_.size());
    upper_start_[static_cast<std::size_t>(k)] = static_cast<int>(upper_.size());
    for (int r = k + 1; r < n; ++r) {
      if (structure_[index(r, k)]) below_.push_back(r);
    }
    for (int j = 0; j < n; ++j) {
      if (j == k || !structure_[index(k, j)]) continue;
      (j < k ? lower_ : upper_).push_back(j);
    }
  }
  below_start_[static_cast<std::size_t>(n)] = static_cast<int>(below_.size());
  lower_start_[static_cast<std::size_t>(n)] = static_cast<int>(lower_.size());
  upper_start_[static_cast<std::size_t>(n)] = static_cast<int>(upper_.size());
  scheduled_ = true;
  ++schedules_;
}

// eliminate()'s work over the schedule's lists; false (lu_ to be redone)
// where A has a nonzero outside the pattern or a pivot is not the largest
// (or is zero or NaN) of its column.
bool SmallLu::factor_by_schedule(const double* A, double largest) {
  // sum |A_i|·outside_i, vectorized: 0 unless a nonzero (or NaN) is outside.
  const Eigen::Map<const Vector> entries(A, n_ * n_);
  if (!(entries.cwiseAbs().cwiseProduct(outside_).sum() == 0.0)) return false;
  for (std::size_t e = 0; e < gather_to_.size(); ++e)
    lu_[static_cast<std::size_t>(gather_to_[e])] = A[gather_from_[e]];
  for (const int f : fill_) lu_[static_cast<std::size_t>(f)] = 0.0;
  double smallest = largest;
  for (int k = 0; k < n_; ++k) {
    const double pivot = at(k, k);
    const int below = below_start_[static_cast<std::size_t>(k)],
              end = below_start_[static_cast<std::size_t>(k + 1)];
    for (int e = below; e < end; ++e) {
      if (std::abs(at(below_[static_cast<std::size_t>(e)], k)) > std::abs(pivot)) return false;
    }
    if (!(std::abs(pivot) > 0.0)) return false;
    smallest = std::min(smallest, std::abs(pivot));
    const double inverse = inverse_pivot_[static_cast<std::size_t>(k)] = 1.0 / pivot;
    const int* u = upper_.data() + upper_start_[static_cast<std::size_t>(k)];
    const int* u_end = upper_.data() + upper_start_[static_cast<std::size_t>(k + 1)];
    const double* pivot_row = &at(k, 0);
    for (int e = below; e < end; ++e) {
      double* row = &at(below_[static_cast<std::size_t>(e)], 0);
      const double l = row[k] *= inverse;
      for (const int* j = u; j != u_end; ++j) row[*j] -= l * pivot_row[*j];
    }
  }
  ratio_ = largest > 0 ? smallest / largest : 0.0;
  return true;
}

// The width of B known at compile time up to 8 columns (P and g_p⁻¹·g_t of
// up to 7 independent coordinates): the multiply-adds along a row unrolled.
void SmallLu::solve_rows(double* B, int cols, int stride) const {
  switch (cols) {
    case 1:
      return substitute<1>(B, cols, stride);
    case 2:
      return substitute<2>(B, cols, stride);
    case 3:
      return substitute<3>(B, cols, stride);
    case 4:
      return substitute<4>(B, cols, stride);
    case 5:
      return substitute<5>(B, cols, stride);
    case 6:
      return substitute<6>(B, cols, stride);
    case 7:
      return substitute<7>(B, cols, stride);
    case 8:
      return substitute<8>(B, cols, stride);
    default:
      return substitute<0>(B, cols, stride);
  }
}

// P·B, then L·Y = P·B forward, U·Z = Y backward, row by row; B = Q·Z. Cols:
// the number of columns when known at compile time (0: cols). The dense path
// works in B (its rows swapped), the sparse one in work_ (B's rows gathered
// in L·U's order, scattered back in Q's).
template <int Cols>
void SmallLu::substitute(double* B, int cols, int stride) const {
  const int width = Cols > 0 ? Cols : cols;
  const auto row_of_B = [&](int i) { return B + static_cast<std::ptrdiff_t>(i) * stride; };
  double* Y = B;
  int step = stride;  // between Y's rows
  if (sparse_) {
    work_.resize(static_cast<std::size_t>(n_ * width));
    Y = work_.data();
    step = width;
    for (int k = 0; k < n_; ++k) {
      const double* from = row_of_B(row_[static_cast<std::size_t>(k)]);
      double* to = Y + static_cast<std::ptrdiff_t>(k) * width;
      for (int c = 0; c < width; ++c) to[c] = from[c];
    }
  } else {
    for (int k = 0; k < n_; ++k) {
      const int p = swap_[static_cast<std::size_t>(k)];
      if (p == k) continue;
      for (int c = 0; c < width; ++c) std::swap(row_of_B(k)[c], row_of_B(p)[c]);
    }
  }
  const auto row = [&](int i) { return Y + static_cast<std::ptrdiff_t>(i) * step; };
  // row(i) -= U_ij·row(j) (or L_ij), i != j
  const auto subtract = [&](int i, int j) {
    const double v = at(i, j);
    double* __restrict to = row(i);
    const double* __restrict from = row(j);
    for (int c = 0; c < width; ++c) to[c] -= v * from[c];
  };
  for (int i = 1; i < n_; ++i) {
    if (!sparse_) {
      for (int j = 0; j < i; ++j) subtract(i, j);
      continue;
    }
    for (int e = lower_start_[static_cast<std::size_t>(i)];
         e < lower_start_[static_cast<std::size_t>(i + 1)]; ++e)
      subtract(i, lower_[static_cast<std::size_t>(e)]);
  }
  for (int i = n_ - 1; i >= 0; --i) {
    if (!sparse_) {
      for (int j = i + 1; j < n_; ++j) subtract(i, j);
    } else {
      for (int e = upper_start_[static_cast<std::size_t>(i)];
           e < upper_start_[static_cast<std::size_t>(i + 1)]; ++e)
        subtract(i, upper_[static_cast<std::size_t>(e)]);
    }
    for (int c = 0; c < width; ++c) row(i)[c] *= inverse_pivot_[static_cast<std::size_t>(i)];
  }
  if (!sparse_) return;
  for (int k = 0; k < n_; ++k) {
    const double* z = row(k);
    double* to = row_of_B(column_[static_cast<std::size_t>(k)]);
    for (int c = 0; c < width; ++c) to[c] = z[c];
  }
}

void SmallLu::solve_in_place(Matrix& b) const {
  for (Eigen::Index c = 0; c < b.cols(); ++c) solve_rows(b.col(c).data(), 1, 1);
}

// Aᵀ = Q·Uᵀ·Lᵀ·P: z = Qᵀ·b, Uᵀ·y = z forward, Lᵀ·w = y backward, then b = Pᵀ·w.
void SmallLu::solve_transposed_in_place(Vector& b) const {
  work_.resize(static_cast<std::size_t>(n_));
  double* z = work_.data();
  for (int k = 0; k < n_; ++k) z[k] = b(column_[static_cast<std::size_t>(k)]);
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j < i; ++j) z[i] -= at(j, i) * z[j];
    z[i] *= inverse_pivot_[static_cast<std::size_t>(i)];
  }
  for (int i = n_ - 1; i >= 0; --i) {
    for (int j = i + 1; j < n_; ++j) z[i] -= at(j, i) * z[j];
  }
  std::copy(z, z + n_, b.data());
  for (int k = n_ - 1; k >= 0; --k) std::swap(b(k), b(swap_[static_cast<std::size_t>(k)]));
}

namespace {

// A row-major matrix's entries in storage order (where Eigen's reductions
// traverse it by columns, entry by entry).
Eigen::Map<const Vector> entries(const RowMajorMatrix& A) {
  return {A.data(), A.size()};
}

// v - v is 0 where v is finite, NaN elsewhere; its sum is vectorized where
// allFinite()'s test entry by entry is not.
template <class V>
bool finite(const V& v) {
  return (v - v).sum() == 0.0;
}

}  // namespace

void LoopClosure::evaluate(const Model& model, double t, const Vector& x) {
  model.constraints(t, x.data(), g_.data(), g_q_.data(), g_p_.data(), g_t_.data());
}

void LoopClosure::factor(const Model& model, double t, const Vector& x) {
  factored_at_last_ = false;
  lu_.factor(g_p_.data(), m_, g_p_largest_);
  if (!(smallest_pivot() >= kSingularPivot)) not_closed(model, t, x, Failure::singular);
}

// Each loop's rows of g_p over the loop's size, its largest entry of [g_q g_p]
// (not the row's own: a row of g_p may vanish at a toggle with its whole
// gradient), then Gaussian elimination with partial pivoting: its smallest
// pivot and the sign of the determinant.
void LoopClosure::measure_singularity(bool always) {
  if (column_.empty()) order_columns();  // at the first solution, as the gate passes or not
  // D = diag(d_l): σ_min(D⁻¹·g_p) >= σ_min(g_p)/max d_l >= min|pivot(g_p)|/(kPivotGap·max d_l)
  if (!always) {
    // max d_l: the largest entry of g_q, or of g_p (given by its LU's pivot ratio)
    const double pivot = lu_.smallest_pivot(), ratio = lu_.smallest_pivot_ratio();
    const double largest =
        std::max(entries(g_q_).cwiseAbs().maxCoeff(), ratio > 0 ? pivot / ratio : 0.0);
    const double bound = largest > 0 ? pivot / (kPivotGap * largest) : 0.0;
    if (bound >= kBranchPoint) {
      singularity_ = {bound, lu_.determinant_sign(), false};
      return;
    }
  }
  std::fill(loop_size_.begin(), loop_size_.end(), 0.0);
  for (int i = 0; i < m_; ++i) {
    double& size = loop_size_[static_cast<std::size_t>(loop_of_[static_cast<std::size_t>(i)])];
    for (int j = 0; j < n_; ++j) size = std::max(size, std::abs(g_q_(i, j)));
    for (int j = 0; j < m_; ++j) size = std::max(size, std::abs(g_p_(i, j)));
  }
  RowMajorMatrix& a = equilibrated_;
  for (int i = 0; i < m_; ++i) {
    const double size = loop_size_[static_cast<std::size_t>(loop_of_[static_cast<std::size_t>(i)])];
    const double scale = size > 0.0 ? 1.0 / size : 1.0;
    for (int k = 0; k < m_; ++k) a(i, k) = scale * g_p_(i, column_[static_cast<std::size_t>(k)]);
  }
  double smallest = std::numeric_limits<double>::infinity();
  int sign = column_parity_;
  for (int k = 0; k < m_; ++k) {
    int p = k;
    for (int i = k + 1; i < m_; ++i) {
      if (std::abs(a(i, k)) > std::abs(a(p, k))) p = i;
    }
    if (p != k) {
      for (int j = 0; j < m_; ++j) std::swap(a(k, j), a(p, j));
      sign = -sign;
    }
    const double pivot = a(k, k);
    smallest = std::min(smallest, std::abs(pivot));
    if (pivot == 0.0) {
      sign = 0;
      continue;
    }
    if (pivot < 0.0) sign = -sign;
    for (int i = k + 1; i < m_; ++i) {
      if (a(i, k) == 0.0) continue;  // a row of another loop
      const double l = a(i, k) / pivot;
      for (int j = k + 1; j < m_; ++j) {
        if (a(k, j) != 0.0) a(i, j) -= l * a(k, j);
      }
    }
  }
  singularity_ = {smallest, sign, true};
}

void LoopClosure::order_columns() {
  column_ = columns_by_sparsity(g_p_.data(), m_);
  column_parity_ = permutation_parity(column_);
}

const LoopClosure::Singularity& LoopClosure::probe(const Model& model, double t, const Vector& q,
                                                   Vector& x) {
  solve(model, t, q, x, true);
  return singularity_;
}

void LoopClosure::solve(const Model& model, double t, const Vector& q, Vector& x, bool probing) {
  x.resize(n_ + m_);
  x.head(n_) = q;
  // From the last solution moved along dp/dq: one Newton step less than from it.
  if (solved_) {
    dq_ = q - last_q_;
    x.tail(m_) = last_p_;
    x.tail(m_).noalias() += T_.bottomRows(m_).lazyProduct(dq_);  // the last solution's P
  } else {
    x.tail(m_) = guess_;
  }
  if (chord_pause_ > 0) --chord_pause_;
  bool polished = false, chord = false;
  for (int iteration = 0;; ++iteration) {
    evaluate(model, t, x);
    if (!(finite(g_) && finite(entries(g_q_)) && finite(entries(g_p_)) && finite(g_t_)))
      not_closed(model, t, x, Failure::not_finite);
    g_p_largest_ = entries(g_p_).cwiseAbs().maxCoeff();  // the LU's too
    const double scale = std::max({1.0, entries(g_q_).cwiseAbs().maxCoeff(), g_p_largest_});
    const double residual = g_.cwiseAbs().maxCoeff();
    const double rounding = 64 * std::numeric_limits<double>::epsilon() * scale;
    // A predicted start within the tolerance is kept as it is (no step, no
    // second evaluation); an iterate of Newton's gets one more step.
    const bool predicted = iteration == 0 && solved_;
    if (chord && residual > rounding) chord_pause_ = kChordPause;
    if (residual <= rounding || ((polished || predicted) && residual <= kTolerance * scale)) break;
    if (iteration == kMaxIterations) not_closed(model, t, x, Failure::no_convergence);
    polished = residual <= kTolerance * scale;
    // Near the last solution its g_p (factored) serves the step, so that g_p
    // is factored once, at the solution: the start's residual r ~ κ·|Δx|²
    // falls to about r·κ·|Δx| (to r² by Newton's step), rounding where the
    // calls are close (along a trajectory); where it is not (the step would
    // cost an evaluation more), Newton's steps for the next kChordPause calls.
    chord =
        predicted && factored_at_last_ && chord_pause_ == 0 && residual <= kChordResidual * scale;
    if (!chord) factor(model, t, x);
    step_ = g_;
    lu_.solve_in_place(step_);
    x.tail(m_) -= step_;
  }
  factor(model, t, x);
  measure_singularity(probing);
  if (!probing && singularity_.pivot < kBranchPoint) not_closed(model, t, x, Failure::branch_point);
  // P = -g_p⁻¹·g_q and g_p⁻¹·g_t in one solve; g_t's column left out where it
  // is zero (loops that do not move with time): so is its solution.
  rates_.leftCols(n_) = g_q_;
  rates_.col(n_) = g_t_;
  const bool steady = (g_t_.array() == 0.0).all();
  lu_.solve_rows(rates_.data(), steady ? n_ : n_ + 1, n_ + 1);
  T_.bottomRows(m_) = -rates_.leftCols(n_);
  solved_ = factored_at_last_ = true;
  last_q_ = q;
  last_p_ = x.tail(m_);
}

void LoopClosure::close_positions(const Model& model, double t, const Vector& q, Vector& x) {
  solve(model, t, q, x);
}

void LoopClosure::close(const Model& model, double t, const Vector& q, const Vector& qd, Vector& x,
                        Vector& xd) {
  solve(model, t, q, x);
  xd.resize(n_ + m_);
  xd.head(n_) = qd;
  xd.tail(m_).noalias() = T_.bottomRows(m_).lazyProduct(qd);
  xd.tail(m_) -= rates_.col(n_);
  model.constraint_bias(t, x.data(), xd.data(), gamma_.data());
  if (!(gamma_.allFinite() && xd.allFinite())) not_closed(model, t, x, Failure::not_finite);
  step_ = -gamma_;
  lu_.solve_in_place(step_);
  c_.tail(m_) = step_;
}

void LoopClosure::derivatives(const Model& model, double t, const Vector& x, const Vector& xd,
                              const Vector& xdd, const Vector& F) {
  // mu = g_p⁻ᵀ·F_p, by lu_ (g_p at the solution, close()).
  mu_ = F.tail(m_);
  lu_.solve_transposed_in_place(mu_);
  model.constraint_derivatives(t, x.data(), xd.data(), xdd.data(), mu_.data(), a_x_rows_.data(),
                               a_xd_rows_.data(), hessian_.data());
  // The row-major arrays read column-major are the transposes: a_x_rows_ = a_xᵀ; H is symmetric.
  const auto a_x = a_x_rows_.transpose(), a_xd = a_xd_rows_.transpose();
  // dxdd/dqd = [0; -g_p⁻¹·a_xd·T]
  aT_.noalias() = -a_xd * T_;
  lu_.solve_in_place(aT_);
  dxdd_dqd_.bottomRows(m_) = aT_;
  // dxd/dq = [0; -g_p⁻¹·(a_xd/2)·T], half of it
  dxd_dq_.bottomRows(m_) = 0.5 * dxdd_dqd_.bottomRows(m_);
  // dxdd/dq = [0; -g_p⁻¹·(a_x·T + a_xd·dxd/dq)]
  aT_.noalias() = -a_x * T_;
  aT_.noalias() -= a_xd * dxd_dq_;
  lu_.solve_in_place(aT_);
  dxdd_dq_.bottomRows(m_) = aT_;
  HT_.noalias() = hessian_ * T_;
  curvature_.noalias() = T_.transpose() * HT_;
  if (!(dxdd_dq_.allFinite() && dxdd_dqd_.allFinite() && curvature_.allFinite()))
    not_closed(model, t, x, Failure::not_finite);
}

void LoopClosure::not_closed(const Model& model, double t, const Vector& x, Failure why,
                             std::string_view where) const {
  // The loops of the equations that fail: those of the largest residual, or
  // those a left null vector of g_p combines (the dependent equations).
  std::vector<int> equations;
  if (why == Failure::singular) {
    const Matrix null = Eigen::FullPivLU<Matrix>(g_p_.transpose()).kernel();
    const Vector w = null.col(0).cwiseAbs();
    for (int k = 0; k < m_; ++k) {
      if (w(k) > 1e-8 * w.maxCoeff()) equations.push_back(k);
    }
  } else if (why == Failure::branch_point) {
    // The equations a left singular vector of the equilibrated g_p for its
    // smallest singular value combines (nearly dependent).
    Matrix scaled = g_p_;
    for (int i = 0; i < m_; ++i) {
      const double size =
          loop_size_[static_cast<std::size_t>(loop_of_[static_cast<std::size_t>(i)])];
      if (size > 0.0) scaled.row(i) /= size;
    }
    const Vector w = Eigen::JacobiSVD<Matrix>(scaled, Eigen::ComputeFullU).matrixU().col(m_ - 1);
    for (int k = 0; k < m_; ++k) {
      if (std::abs(w(k)) > 1e-3 * w.cwiseAbs().maxCoeff()) equations.push_back(k);
    }
  } else {
    Eigen::Index worst = 0;
    g_.cwiseAbs().maxCoeff(&worst);
    equations.push_back(static_cast<int>(worst));
  }
  std::vector<std::string> loops;
  for (int k : equations) {
    const std::string name =
        fmt::format("'{}'", model.loop_names()[static_cast<std::size_t>(model.constraint_loop(k))]);
    if (std::find(loops.begin(), loops.end(), name) == loops.end()) loops.push_back(name);
  }
  std::string state;
  for (int j = 0; j < n_ + m_; ++j) {
    state +=
        fmt::format("{}{} = {}", j ? ", " : "", model.q_names()[static_cast<std::size_t>(j)], x(j));
  }
  const std::string which =
      fmt::format("loop{} {}", loops.size() == 1 ? "" : "s", fmt::join(loops, ", "));
  std::string what;
  if (why == Failure::singular) {
    what = fmt::format(
        "{} at a singular configuration: g_p (the Jacobian of the loop equations with respect to "
        "the implicit dependent parameters) is singular (smallest pivot {:.3g} of its largest "
        "entry), a toggle or dead-centre position where q does not determine them",
        which, smallest_pivot());
  } else if (why == Failure::branch_point) {
    what = fmt::format(
        "{} at a branch point: g_p (the Jacobian of the loop equations with respect to the "
        "implicit dependent parameters), each loop's rows over that loop's largest entry of [g_q "
        "g_p], has a smallest pivot {:.3g}, below {:g}, where the rates of the dependent "
        "parameters have lost more than half their digits: a toggle, dead-centre or branch point "
        "where q does not determine them",
        which, singularity_.pivot, kBranchPoint);
  } else if (why == Failure::not_finite) {
    what = fmt::format("{}: the loop equations are not finite", which);
  } else {
    what = fmt::format(
        "{} do{} not close: Newton's iteration on the implicit dependent parameters did not "
        "converge in {} iterations (|g| = {:.3g})",
        which, loops.size() == 1 ? "es" : "", kMaxIterations, g_.cwiseAbs().maxCoeff());
  }
  throw NumericError(fmt::format("t = {}: {}{} at ({})", t, what, where, state));
}

}  // namespace symdyn::runtime
