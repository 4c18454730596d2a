#pragma once
// Solves M·x = b for the symmetric positive definite mass matrix, factored as
// M = L·Lᵀ (Cholesky) in storage sized once: nothing allocates after
// construction, so it serves the integrators' step loop.
//
// The factorization is one column loop, L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj,
// the sum in increasing k, written twice with the same operations in the same
// order: plain up to kFactorLoopUpTo coordinates, vectorized across rows
// (detail/dense_kernels.hpp) above, where it is up to twice faster than the
// plain loop and than Eigen's blocked LLT (bench/results/derivatives.md). Never
// fused, so the factor is the same to the bit on every processor and at every
// size either way.
//
// The solves of several right-hand sides run kernels compiled twice
// (detail/dense_kernels.hpp): for the build's instruction set and, on x86-64,
// for AVX2 with FMA, taken where the processor runs it. The two agree to
// rounding, not to the bit; the factorization and the single right-hand side
// solves are the same on every processor.
//
// M is refused when it is not positive definite, or when a pivot of
// L·D·Lᵀ (D_k = L_kk²) is within rounding of zero against its own
// coordinate's diagonal, D_k <= kSingularRatio·M_kk: the coordinate's inertia
// is all used up by the coordinates before it (two coordinates that move the
// bodies the same way, as at a gimbal lock, or a coordinate that moves no
// mass). Per coordinate, so a light coordinate beside heavy ones, or a nearly
// locked gimbal that still has a few digits of inertia left, passes.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

namespace detail {
struct DenseKernels;  // detail/dense_kernels.hpp, not installed
}  // namespace detail

class SpdSolver {
 public:
  // Which compiled kernels: the widest the processor runs (best), or one
  // forced (tests and benchmarks compare them); wide throws std::invalid_argument
  // where !wide_kernels_available().
  enum class Kernels { best, plain, wide };

  explicit SpdSolver(int n = 0, Kernels kernels = Kernels::best);

  // AVX2 with FMA: built (x86-64) and run by this processor.
  static bool wide_kernels_available();
  // "plain" or "avx2": the kernels this solver runs.
  const char* kernels_name() const;

  int size() const { return static_cast<int>(L_.rows()); }

  // Factors M (n x n; only its lower triangle is read). False when M is
  // refused (see above) or not n x n: then solve_in_place must not be called.
  bool factor(const Matrix& M);

  // b := M⁻¹·b (n).
  void solve_in_place(Vector& b) const;

  // x := -M⁻¹·b (n, x sized): the negation folded into the forward substitution
  // (M·qdd = -h without a pass to negate h).
  void solve_negated(const Vector& b, Vector& x) const;

  // B := M⁻¹·B and B := -M⁻¹·B (n x m), all columns in one solve, so that the
  // multiply-adds are independent across the columns (column by column each
  // entry is a chain of dependent ones): up to kInPlaceUpTo coordinates row
  // by row in place, above them tiles of up to detail::kWidestTile (16) columns
  // copied row by row, three rows' sums at a time in registers.
  void solve_in_place(Matrix& B);
  void solve_negated_in_place(Matrix& B);
  // X := -M⁻¹·B (n x m) for B row-major, as the emitted code writes the
  // derivatives: read row by row into the tiles, with no pass to turn it first.
  void solve_negated(const RowMajorMatrix& B, Matrix& X);

  // min_k D_k / M_kk of the last factorization: the share of its own
  // inertia the worst coordinate has left (<= 0: M is not positive definite).
  double smallest_pivot_ratio() const { return smallest_ratio_; }

  // Below this a pivot is rounding: 64 ulps of the diagonal it came from.
  static constexpr double kSingularRatio = 64 * 2.220446049250313e-16;
  // Single right-hand sides: up to this size the column loop, above it Eigen's
  // triangular solves.
  static constexpr int kLoopUpTo = 40;
  // The factorization: up to this size the plain column loop, above it the
  // kernels' (the same factor to the bit).
  static constexpr int kFactorLoopUpTo = 20;
  // Several right-hand sides up to this size: row by row on B in place (its
  // rows strided), where copying tiles costs more than it saves.
  static constexpr int kInPlaceUpTo = 3;

 private:
  bool factor_by_columns(const Matrix& M);
  template <bool negate>
  void solve_matrix(Matrix& B);
  template <bool negate>
  void solve_rows_in_place(Matrix& B) const;
  template <bool negate>
  void solve(const double* b, Vector& out) const;
  // x := ±M⁻¹·b by the column loop (n <= kLoopUpTo); b may be x.
  template <bool negate>
  void substitute(const double* b, double* x) const;
  Matrix L_;  // (n x n) its lower triangle is L
  const detail::DenseKernels* kernels_;
  std::vector<double> tile_;  // n x detail::kWidestTile (16): columns of B row by row
  double smallest_ratio_ = 0.0;
};

// The direction in which a square A (n x n) is (nearly) singular, in
// coordinate names (name(j) names coordinate j): the right singular vector of
// its smallest singular value, by the components that make up 99 % of it,
// "'x'" or "'psi' (0.71), 'phi' (-0.71)". For error messages: it allocates.
std::string null_direction(const Matrix& A, const std::function<std::string(int)>& name);

// Why a symmetric mass matrix M was refused, from its smallest eigenvalue's
// direction: "coordinate 'x' moves no mass", "coordinates 'psi' (0.71) and
// 'phi' (-0.71) move the bodies the same way" or "it is indefinite along ...".
std::string mass_matrix_singularity(const Matrix& M, const std::function<std::string(int)>& name);

}  // namespace symdyn::runtime
