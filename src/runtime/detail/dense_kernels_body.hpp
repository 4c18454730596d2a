// The dense kernels of dense_kernels.hpp, written once. Included by one source
// per instruction set, inside that set's own namespace, after defining kName,
// kTile (the columns of B a solve keeps in registers: 16 doubles are eight
// SSE2 registers, 32 eight AVX2 ones; the factorization keeps kTile / 2 rows of
// a column), kTilesUpTo and multiply_subtract(a, b, c)
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

// Rows i0 .. i0 + R - 1 of column j: L_ij := L_ij - Σ_k<j L_ik·L_jk, k increasing, the R sums in
// registers across k. Never fused (a multiply, then a subtraction): the textbook loop's operations
// in its order, so every kernel's factor is that loop's to the bit.
template <int R>
void subtract_columns_before(int n, int j, int i0, double* __restrict L) {
  double sum[R];
  for (int r = 0; r < R; ++r) sum[r] = L[i0 + r + j * n];
  for (int k = 0; k < j; ++k) {
    const double c = L[j + k * n];
    const double* __restrict column = L + k * n + i0;
    for (int r = 0; r < R; ++r) sum[r] = sum[r] - column[r] * c;
  }
  for (int r = 0; r < R; ++r) L[i0 + r + j * n] = sum[r];
}

// M = L·Lᵀ left-looking, column by column: L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj (i > j),
// L_jj = sqrt(M_jj - Σ_k<j L_jk²), rows in chunks of kTile / 2 (then 8, 4, 1). ratio: min_j
// D_j / M_jj (D_j = L_jj²); false at the first D_j not > 0 (NaN too), ratio then D_j / M_jj
// where D_j < 0 < M_jj, else 0.
bool factor(int n, const double* __restrict M, double* __restrict L, double* ratio) {
  constexpr int kRows = kTile / 2;
  double smallest = 1.0;
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) L[i + j * n] = M[i + j * n];
    int i = j;
    for (; i + kRows <= n; i += kRows) subtract_columns_before<kRows>(n, j, i, L);
    if constexpr (kRows > 8) {
      if (i + 8 <= n) subtract_columns_before<8>(n, j, i, L), i += 8;
    }
    if (i + 4 <= n) subtract_columns_before<4>(n, j, i, L), i += 4;
    for (; i < n; ++i) subtract_columns_before<1>(n, j, i, L);
    const double d = L[j + j * n], diagonal = M[j + j * n];
    if (!(d > 0.0)) {
      *ratio = d < 0.0 && diagonal > 0.0 ? d / diagonal : 0.0;
      return false;
    }
    smallest = d / diagonal < smallest ? d / diagonal : smallest;
    const double Ljj = __builtin_sqrt(d);
    L[j + j * n] = Ljj;
    for (int r = j + 1; r < n; ++r) L[r + j * n] = L[r + j * n] / Ljj;
  }
  *ratio = smallest;
  return true;
}

const DenseKernels kernels{kName, kTilesUpTo, solve, factor};
