#pragma once
// Closed kinematic loops by coordinate partitioning (Wehage and Haug; as
// Robotran): the tree's extended coordinates x = (q, p) hold the independent
// coordinates q (the state integrated) and the implicit dependent parameters
// p, which the loops' equations g(t, q, p) = 0 determine (docs/builder.md).
// At each state:
//
//   p:   Newton's iteration g_p·Δp = -g from the last solution (moved along
//        dp/dq from its q) or the model's guesses, to |g| <= 1e-12·s, s the
//        largest entry of [g_q g_p] (at least 1), with one more step after it
//        (none where the start moved from the last solution is within it;
//        from such a start close to it, the step with its g_p, so that g_p
//        is factored once, at the solution);
//   pd = P·qd - g_p⁻¹·g_t,            P = -g_p⁻¹·g_q   (ncon x n);
//   xdd = T·qdd + c,  T = [I; P],     c = [0; -g_p⁻¹·gamma].
//
// The tree's M_x·xdd + h_x = Q_x + g_xᵀ·λ then reduces (Tᵀ·g_xᵀ = 0) to
//   (Tᵀ·M_x·T)·qdd = Tᵀ·(Q_x - h_x - M_x·c).
// The exact Jacobians of the reduced residual f = Tᵀ·F(x, xd, xdd), F the
// tree's, differentiate T, xd and xdd too. With a = g_x·xdd + gamma (a = 0
// is the loops' equations twice differentiated in time) and its emitted
// a_x = ∂a/∂x, a_xd = ∂a/∂xd = 2·∂(g_x·xd + g_t)/∂x:
//   dx/dq = dxd/dqd = dxdd/dqdd = T,
//   dxd/dq   = [0; -g_p⁻¹·(a_xd/2)·T],
//   dxdd/dqd = [0; -g_p⁻¹·a_xd·T],
//   dxdd/dq  = [0; -g_p⁻¹·(a_x·T + a_xd·dxd/dq)],
//   (dT/dq_j)ᵀ·F = -Tᵀ·H·T·e_j,  H = ∂²(mu·g)/∂x², mu = g_p⁻ᵀ·F_p
// (dP/dq_j = -g_p⁻¹·∂(g_x·T·e_j)/∂x·T, and H is symmetric), so that
//   K = Tᵀ·(K_x·T + C_x·dxd/dq + M_x·dxdd/dq) - Tᵀ·H·T,
//   C = Tᵀ·(C_x·T + M_x·dxdd/dqd),   M = Tᵀ·M_x·T.
//
// A loop that does not close (no convergence in kMaxIterations, a value not
// finite) or a singular g_p (a toggle or dead-centre position: p not
// determined by q) is a NumericError naming the loop, the time and the state.
// Singular short of exactly: each solution's g_p with each loop's rows divided
// by that loop's largest entry of [g_q g_p] (its size, in its units) has a
// smallest pivot r; p carries rounding of about 1e-16/r and its rates pd, pdd
// about 1e-16/r² of themselves (g_p's change along the error in p), half
// their digits at r = kBranchPoint, where the solution is refused.

#include <Eigen/LU>
#include <string_view>
#include <vector>

#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

// LU factorization with partial pivoting of a small square matrix (g_p: a
// few rows per loop), by plain loops: Eigen's PartialPivLU dispatches to
// blocked kernels whose set-up costs more than the arithmetic at this size.
// P·A·Q = L·U, L unit lower triangular. Sparse A (each loop's equations
// involve its own parameters and a few shared ones) costs little: Q takes the
// columns with fewest nonzeros first (counted at the first factor(), so that
// a loop's own parameters are eliminated within its rows before the shared
// ones fill in), and the elimination skips exact zeros. Its pivots and
// structure (A's nonzeros, the fill-in) are then kept as a schedule: the next
// factor() of an A whose nonzeros stay within those seen and whose pivots stay
// the largest of their columns (along a trajectory) runs over its lists only,
// the rows in place; any other A is factored anew (the schedule remade), so
// that every A is factored exactly, by partial pivoting. The solves run over
// L's and U's nonzeros. A small or dense A (one loop) has Q = I and no
// schedule, and solves over all of L and U: the lists would cost more than
// they save. No allocation after the first factor().
class SmallLu {
 public:
  // The sparse path pays above this size, where at most this share of A's
  // entries are nonzero (at the first factor()).
  static constexpr int kDenseUpTo = 4;
  static constexpr double kSparseShare = 0.6;

  // sparse_if_it_pays false: always the dense path (to compare the two).
  explicit SmallLu(bool sparse_if_it_pays = true) : sparse_if_it_pays_(sparse_if_it_pays) {}
  // A (n x n) row-major, as the emitted arrays are; largest: its largest |entry|.
  void factor(const double* A, int n);
  void factor(const double* A, int n, double largest);
  // The path chosen at the first factor(): Q by sparsity and lists of nonzeros.
  bool sparse() const { return sparse_; }
  // How many times the sparse path's schedule was made (at the first factor()
  // and at each A that did not fit it).
  int schedules() const { return schedules_; }
  // The smallest |pivot| over the largest |entry| of A (0 for a zero A).
  double smallest_pivot_ratio() const { return ratio_; }
  // The smallest |pivot| (U's diagonal) and the sign of det(A) (0 if singular).
  double smallest_pivot() const;
  int determinant_sign() const;
  // b := A⁻¹·b (each column of b).
  void solve_in_place(Vector& b) const { solve_rows(b.data(), 1, 1); }
  void solve_in_place(Matrix& b) const;
  // B := A⁻¹·B, B (n x cols) row-major, its rows `stride` apart: all columns
  // in one pass, the multiply-adds independent across them.
  void solve_rows(double* B, int cols, int stride) const;
  void solve_rows(double* B, int cols) const { solve_rows(B, cols, cols); }
  // b := A⁻ᵀ·b
  void solve_transposed_in_place(Vector& b) const;

 private:
  // Q: the columns with fewest nonzeros first (stable), where sparse_.
  void order_columns(const double* A);
  // Partial pivoting over all of A (largest: A's largest |entry|).
  void eliminate(const double* A, double largest);
  // The schedule of eliminate()'s pivots, and factor() by it (false: not A's).
  void schedule(const double* A);
  bool factor_by_schedule(const double* A, double largest);
  template <int Cols>
  void substitute(double* B, int cols, int stride) const;
  double& at(int i, int j) { return lu_[static_cast<std::size_t>(i * n_ + j)]; }
  double at(int i, int j) const { return lu_[static_cast<std::size_t>(i * n_ + j)]; }

  int n_ = 0;
  bool sparse_if_it_pays_ = true, sparse_ = false;
  std::vector<double> lu_;             // L below the diagonal, U on and above it (n x n) row-major
  std::vector<int> swap_;              // row k was swapped with row swap_[k] at step k
  std::vector<int> pivot_row_;         // the columns of step k's pivot row to eliminate with
  std::vector<int> column_;            // Q: column k of L·U is A's column column_[k]
  bool permuted_ = false;              // Q is not the identity
  int column_parity_ = 1;              // Q's parity (+-1)
  std::vector<double> inverse_pivot_;  // 1/U_kk: the solves multiply
  // The columns of L's and U's row i that can hold a nonzero (the schedule's,
  // where sparse_; the dense path reads lu_'s rows whole): [*_start_[i],
  // *_start_[i + 1]) of lower_, upper_.
  std::vector<int> lower_, upper_;
  std::vector<int> lower_start_, upper_start_;
  // The schedule (where sparse_): row k of L·U is A's row row_[k]; A's entries
  // ever nonzero (pattern_, n x n as A), taken from gather_from_ to lu_'s
  // gather_to_, the others (where outside_ is 1) zero; lu_'s fill-in fill_; L's column k
  // the rows below_[below_start_[k]..below_start_[k + 1]).
  bool scheduled_ = false;
  int schedules_ = 0;
  std::vector<int> row_, gather_from_, gather_to_, fill_, below_, below_start_;
  Vector outside_;
  std::vector<char> pattern_, structure_;  // structure_: L·U's nonzeros (n x n), schedule()'s
  mutable std::vector<double> work_;       // the sparse solve's rows (n x cols)
  double ratio_ = 0.0;
};

class LoopClosure {
 public:
  static constexpr int kMaxIterations = 25;
  static constexpr double kTolerance = 1e-12;  // on |g|, times the scale s above
  // Below this share of g_p's largest entry a pivot of its LU factorization
  // is singular.
  static constexpr double kSingularPivot = 1e-13;
  // Below this smallest pivot of the equilibrated g_p (above) a solution is
  // refused: pd and pdd have lost more than half their digits.
  static constexpr double kBranchPoint = 1e-4;
  // The gap allowed between a pivot of g_p and its smallest singular value:
  // the equilibrated g_p is measured only where the bound from the LU of g_p
  // (measure_singularity()) is below kBranchPoint.
  static constexpr double kPivotGap = 100;
  // The step from a predicted start within kChordResidual (times s) is made
  // with the last solution's g_p, except for kChordPause calls after one that
  // did not reach rounding.
  static constexpr double kChordResidual = 1e-6;
  static constexpr int kChordPause = 16;

  LoopClosure() = default;
  explicit LoopClosure(const Model& model);

  // x = (q, p) and xd = (qd, pd) closing the loops at (t, q, qd) (n each),
  // with T and c for the accelerations.
  void close(const Model& model, double t, const Vector& q, const Vector& qd, Vector& x,
             Vector& xd);
  // Only p: x closing the loops at (t, q) (P too, but not c).
  void close_positions(const Model& model, double t, const Vector& q, Vector& x);

  const Matrix& T() const { return T_; }  // (nq x n)
  const Vector& c() const { return c_; }  // (nq)
  // The multipliers λ = g_p⁻ᵀ·r_p (ncon) of M_x·xdd + h_x - Q_x = r_x = g_xᵀ·λ,
  // from the p rows r_p (ncon) of the tree's residual at the last close().
  void multipliers(const Vector& r_p, Vector& lambda) const {
    lambda = r_p;
    lu_.solve_transposed_in_place(lambda);
  }

  // After close() at (t, q, qd), giving x and xd: the derivatives above at
  // xdd (nq) with F the tree's residual there (nq), from the emitted
  // constraint_derivatives (the model must have them).
  void derivatives(const Model& model, double t, const Vector& x, const Vector& xd,
                   const Vector& xdd, const Vector& F);
  const Matrix& dxd_dq() const { return dxd_dq_; }        // (nq x n)
  const Matrix& dxdd_dq() const { return dxdd_dq_; }      // (nq x n)
  const Matrix& dxdd_dqd() const { return dxdd_dqd_; }    // (nq x n)
  const Matrix& curvature() const { return curvature_; }  // Tᵀ·H·T (n x n)

  // The equilibrated g_p at the last solution: its smallest pivot r (above)
  // and the sign of its determinant (that of g_p), which changes where a
  // motion crosses from one branch to another (0 where exactly singular).
  // Not measured (measured false) where g_p's own LU bounds r from below by
  // kBranchPoint or more: pivot is then that bound.
  struct Singularity {
    double pivot = 1.0;
    int sign = 1;
    bool measured = true;
  };
  const Singularity& singularity() const { return singularity_; }
  // close_positions() without refusing a solution near a branch point, r
  // measured (to look for one between evaluations), and the refusal of the
  // last one (where: said after the loops' words).
  const Singularity& probe(const Model& model, double t, const Vector& q, Vector& x);
  [[noreturn]] void refuse_branch_point(const Model& model, double t, const Vector& x,
                                        std::string_view where) const {
    not_closed(model, t, x, Failure::branch_point, where);
  }

  // The next close() starts from the guesses: the model's, or those given
  // (ncon, to choose an assembly: the solution Newton's iteration reaches).
  void reset() { solved_ = false; }
  void set_guess(const Vector& p) {
    guess_ = p;
    reset();
  }

 private:
  // probing: r measured, no refusal (probe()).
  void solve(const Model& model, double t, const Vector& q, Vector& x, bool probing = false);
  // Factors g_p_, a NumericError naming the loops when singular.
  void factor(const Model& model, double t, const Vector& x);
  double smallest_pivot() const { return lu_.smallest_pivot_ratio(); }
  void evaluate(const Model& model, double t, const Vector& x);
  // singularity_ of g_p_ at the solution (g_q_ too: the loops' sizes),
  // from lu_ alone where its bound is at least kBranchPoint (unless `always`).
  void measure_singularity(bool always);
  void order_columns();
  enum class Failure { singular, not_finite, no_convergence, branch_point };
  [[noreturn, gnu::cold]] void not_closed(const Model& model, double t, const Vector& x,
                                          Failure why, std::string_view where = "") const;

  int n_ = 0, m_ = 0;
  Vector g_, g_t_, gamma_, guess_, step_, dq_;
  RowMajorMatrix g_q_, g_p_;  // as emitted
  double g_p_largest_ = 0.0;  // g_p's largest |entry|
  RowMajorMatrix rates_;      // g_p⁻¹·[g_q g_t] (ncon x (n + 1))
  SmallLu lu_;
  Matrix T_;  // [I; P], P that of the last solution
  Vector c_;
  bool solved_ = false;
  bool factored_at_last_ = false;  // lu_ holds g_p at the last solution
  Vector last_q_, last_p_;         // the last solution, the start of the next
  int chord_pause_ = 0;            // calls left without the last solution's g_p
  // derivatives(): the emitted arrays (row-major, so held transposed) and results
  Vector mu_;
  Matrix a_x_rows_, a_xd_rows_, hessian_, aT_, HT_;
  Matrix dxd_dq_, dxdd_dq_, dxdd_dqd_, curvature_;
  // measure_singularity(): each equation's loop, each loop's size, the equilibrated g_p
  // with its columns of fewest nonzeros first (at the first call: a loop's own
  // parameters eliminated within its rows), that order's parity (+-1)
  std::vector<int> loop_of_, column_;
  std::vector<double> loop_size_;
  RowMajorMatrix equilibrated_;
  int column_parity_ = 1;
  Singularity singularity_;
};

}  // namespace symdyn::runtime
