// The dense kernels of dense_kernels.hpp, written once. Included by one source
// per instruction set, inside that set's own namespace, after defining kName,
// kTile (the columns of B a solve keeps in registers: 16 doubles are eight
// SSE2 registers, 32 eight AVX2 ones), kTilesUpTo and multiply_subtract(a, b, c)
// = a - b·c (fused where the set has FMA). No #pragma once: each includer
// compiles it. Plain loops with no library calls, so that everything here is
// compiled for the includer's instruction set and vectorized by the compiler.

// `count` <= W columns of B from column j0, copied row by row into R (n x W,
// row-major, the columns beyond count zero), solved and copied back. Forward,
// row by row: R_i := (±R_i - Σ_k<i L_ik·R_k) / L_ii, then backward:
// R_i := (R_i - Σ_k>i L_ki·R_k) / L_ii. Each row's W sums stay in registers
// across k, independent of one another: W/4 (or W/2) vector multiply-adds per
// entry of L, where a column alone is a chain of dependent ones.
template <int W>
void solve_tile(int n, const double* __restrict L, double* __restrict B, int j0, int count,
                double sign, double* __restrict R) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < W; ++j) R[i * W + j] = j < count ? B[i + (j0 + j) * n] : 0.0;
  }
  for (int i = 0; i < n; ++i) {
    double sum[W];
    for (int j = 0; j < W; ++j) sum[j] = sign * R[i * W + j];
    for (int k = 0; k < i; ++k) {
      const double c = L[i + k * n];
      for (int j = 0; j < W; ++j) sum[j] = multiply_subtract(sum[j], c, R[k * W + j]);
    }
    const double inverse = 1.0 / L[i + i * n];
    for (int j = 0; j < W; ++j) R[i * W + j] = sum[j] * inverse;
  }
  for (int i = n - 1; i >= 0; --i) {
    double sum[W];
    for (int j = 0; j < W; ++j) sum[j] = R[i * W + j];
    for (int k = i + 1; k < n; ++k) {
      const double c = L[k + i * n];
      for (int j = 0; j < W; ++j) sum[j] = multiply_subtract(sum[j], c, R[k * W + j]);
    }
    const double inverse = 1.0 / L[i + i * n];
    for (int j = 0; j < W; ++j) R[i * W + j] = sum[j] * inverse;
  }
  for (int j = 0; j < count; ++j) {
    for (int i = 0; i < n; ++i) B[i + (j0 + j) * n] = R[i * W + j];
  }
}

// Tiles of kTile columns, then the rest in one tile of the narrowest width
// that holds it (at most twice its columns).
void solve(int n, const double* L, double* B, int m, bool negate, double* R) {
  const double sign = negate ? -1.0 : 1.0;
  int j = 0;
  for (; j + kTile <= m; j += kTile) solve_tile<kTile>(n, L, B, j, kTile, sign, R);
  const int rest = m - j;
  if (rest > 16) {
    solve_tile<kTile>(n, L, B, j, rest, sign, R);
  } else if (rest > 8) {
    solve_tile<16>(n, L, B, j, rest, sign, R);
  } else if (rest > 4) {
    solve_tile<8>(n, L, B, j, rest, sign, R);
  } else if (rest > 0) {
    solve_tile<4>(n, L, B, j, rest, sign, R);
  }
}

const DenseKernels kernels{kName, kTilesUpTo, solve};
