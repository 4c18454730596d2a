#pragma once
// SpdSolver's solves of several right-hand sides, compiled twice: for the build's own instruction
// set (plain) and, on x86-64, once more for AVX2 with FMA (wide: four doubles
// a register and fused multiply-adds), the one chosen when the processor runs
// it. One source (dense_kernels_body.hpp) serves both, in a namespace of its
// own per instruction set, so no symbol of the wide build can stand in for a
// plain one at link time. The wide results may differ from the plain ones in
// the last bits (FMA rounds once where a multiply and a subtraction round twice).
// The factorization is here too, vectorized across rows but never fused: the
// same operations in the same order in every kernel, so it is the same to the
// bit on every processor.

namespace symdyn::runtime::detail {

// The right-hand sides B (n x m) of a solve: entry (i, j) at in[i·row_step +
// j·column_step] (column-major: 1 and n; row-major, as the emitted code writes
// its matrices: m and 1); the solution X (n x m) written column-major at out,
// which may be in where B is column-major.
struct RightHandSides {
  const double* in;
  int row_step, column_step;
  double* out;
  int m;
};

struct DenseKernels {
  const char* name;  // "plain", "avx2"
  // X := ±M⁻¹·B = ±L⁻ᵀ·L⁻¹·B, L (n x n, column-major) M's Cholesky factor in
  // its lower triangle; tile: a workspace of n x kWidestTile doubles. Faster
  // than Eigen's blocked triangular solves at every size measured
  // (bench/results/derivatives.md).
  void (*solve)(int n, const double* L, RightHandSides B, bool negate, double* tile);
  // M = L·Lᵀ (n x n, column-major; M's lower triangle read, L's written), the
  // same to the bit in every kernel: false where a pivot D_j = L_jj² is not
  // > 0; ratio: min_j D_j / M_jj (SpdSolver::smallest_pivot_ratio()).
  bool (*factor)(int n, const double* M, double* L, double* ratio);
};

// The widest tile of columns a solve copies row by row (AVX2: four vectors of four).
inline constexpr int kWidestTile = 16;

const DenseKernels& plain_dense_kernels();
// nullptr where the build or the processor has no AVX2 with FMA.
const DenseKernels* wide_dense_kernels();

}  // namespace symdyn::runtime::detail
