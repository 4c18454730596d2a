#pragma once
// Closed kinematic loops by coordinate partitioning (Wehage and Haug; as
// Robotran): the tree's extended coordinates x = (q, p) hold the independent
// coordinates q (the state integrated) and the implicit dependent parameters
// p, which the loops' equations g(t, q, p) = 0 determine (docs/builder.md).
// At each state:
//
//   p:   Newton's iteration g_p·Δp = -g from the last solution (moved along
//        dp/dq from its q) or the model's guesses, to |g| <= 1e-12·s, s the
//        largest entry of [g_q g_p] (at least 1), with one more step after it;
//   pd = P·qd - g_p⁻¹·g_t,            P = -g_p⁻¹·g_q   (ncon x n);
//   xdd = T·qdd + c,  T = [I; P],     c = [0; -g_p⁻¹·gamma].
//
// The tree's M_x·xdd + h_x = Q_x + g_xᵀ·λ then reduces (Tᵀ·g_xᵀ = 0) to
//   (Tᵀ·M_x·T)·qdd = Tᵀ·(Q_x - h_x - M_x·c).
// A loop that does not close (no convergence in kMaxIterations, a value not
// finite) or a singular g_p (a toggle or dead-centre position: p not
// determined by q) is a NumericError naming the loop, the time and the state.

#include <Eigen/LU>

#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

class LoopClosure {
 public:
  static constexpr int kMaxIterations = 25;
  static constexpr double kTolerance = 1e-12;  // on |g|, times the scale s above
  // Below this share of g_p's largest entry a pivot of its LU factorization
  // is singular.
  static constexpr double kSingularPivot = 1e-13;

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
    lambda.noalias() = lu_.transpose().solve(r_p);
  }

  // The next close() starts from the guesses: the model's, or those given
  // (ncon, to choose an assembly: the solution Newton's iteration reaches).
  void reset() { solved_ = false; }
  void set_guess(const Vector& p) {
    guess_ = p;
    reset();
  }

 private:
  void solve(const Model& model, double t, const Vector& q, Vector& x);
  // Factors g_p_, a NumericError naming the loops when singular.
  void factor(const Model& model, double t, const Vector& x);
  double smallest_pivot() const;  // of lu_, as a share of g_p's largest entry
  void evaluate(const Model& model, double t, const Vector& x);
  enum class Failure { singular, not_finite, no_convergence };
  [[noreturn, gnu::cold]] void not_closed(const Model& model, double t, const Vector& x,
                                          Failure why) const;

  int n_ = 0, m_ = 0;
  Vector g_, g_t_, gamma_, guess_, step_, dq_;
  Matrix g_q_, g_p_;  // column-major copies of the emitted row-major arrays
  Matrix g_q_rows_, g_p_rows_;
  Eigen::PartialPivLU<Matrix> lu_;
  Matrix P_, T_;
  Vector c_;
  bool solved_ = false;
  Vector last_q_, last_p_;  // the last solution, the start of the next
  Matrix last_P_;
};

}  // namespace symdyn::runtime
