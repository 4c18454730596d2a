// The dense kernels of dense_kernels.hpp, written once. Included by one source
// per instruction set, inside that set's own namespace, after defining kName,
// kLanes (the doubles of one vector register), the type Vector (kLanes doubles,
// a GCC vector), multiply_subtract(a, b, c) = a - b·c for a vector a and c and
// a double b (fused where the set has FMA) and kFactorRows (the rows of a
// column the factorization keeps in registers). No #pragma once: each includer
// compiles it. No library calls, so that everything here is compiled for the
// includer's instruction set.

inline Vector load(const double* p) {
  Vector v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

inline void store(double* p, Vector v) {
  __builtin_memcpy(p, &v, sizeof v);
}

// A solve keeps kRows rows of kVectors vectors in registers: 12 sums, so that
// each vector of a solved row loaded serves three rows of L, and each entry of
// L broadcast four vectors, where the 16 registers of SSE2 or AVX2 allow.
constexpr int kRows = 3, kVectors = 4, kTile = kVectors * kLanes;
static_assert(kTile <= kWidestTile);

// Rows i = first, first + step, .. (rb of them; step 1 forward, -1 backward) of
// a tile R of V vectors a row (row-major): forward R_i := (±R_i - Σ_k<i L_ik·R_k)
// / L_ii, backward R_i := (R_i - Σ_k>i L_ki·R_k) / L_ii, first over the rows
// solved before the block, with every row's sums in registers, then within it.
template <int rb, int V, bool forward>
void solve_rows(int n, const double* __restrict L, double* __restrict R, int first, double sign) {
  constexpr int W = V * kLanes, step = forward ? 1 : -1;
  // The factor of row i's term in row k: L_ik forward, L_ki backward.
  const auto l = [&](int i, int k) { return forward ? L[i + k * n] : L[k + i * n]; };
  Vector sum[rb][V];
  for (int r = 0; r < rb; ++r) {
    for (int v = 0; v < V; ++v) sum[r][v] = sign * load(R + (first + r * step) * W + v * kLanes);
  }
  const int begin = forward ? 0 : first + 1, end = forward ? first : n;
  for (int k = begin; k < end; ++k) {
    Vector x[V];
    for (int v = 0; v < V; ++v) x[v] = load(R + k * W + v * kLanes);
    for (int r = 0; r < rb; ++r) {
      const double c = l(first + r * step, k);
      for (int v = 0; v < V; ++v) sum[r][v] = multiply_subtract(sum[r][v], c, x[v]);
    }
  }
  for (int r = 0; r < rb; ++r) {
    const int i = first + r * step;
    for (int p = 0; p < r; ++p) {
      const double c = l(i, first + p * step);
      for (int v = 0; v < V; ++v) sum[r][v] = multiply_subtract(sum[r][v], c, sum[p][v]);
    }
    const double inverse = 1.0 / L[i + i * n];
    for (int v = 0; v < V; ++v) {
      sum[r][v] = sum[r][v] * inverse;
      store(R + i * W + v * kLanes, sum[r][v]);
    }
  }
}

// The kLanes x kLanes block at `from` (its rows `from_step` apart) written
// turned at `to` (its rows `to_step` apart), through registers.
inline void turn_block(const double* from, int from_step, double* to, int to_step) {
  Vector row[kLanes];
  for (int r = 0; r < kLanes; ++r) row[r] = load(from + r * from_step);
  for (int c = 0; c < kLanes; ++c) {
    Vector column;
    for (int r = 0; r < kLanes; ++r) column[r] = row[r][c];
    store(to + c * to_step, column);
  }
}

// Columns j0 .. j0 + count - 1 of B into the tile R (W doubles a row), the
// columns beyond count zero: row by row where B is row-major, else in turned
// blocks, the edges one by one.
template <int W>
void copy_in(int n, const RightHandSides& B, int j0, int count, double* __restrict R) {
  if (B.column_step == 1) {
    for (int i = 0; i < n; ++i) {
      const double* row = B.in + i * B.row_step + j0;
      for (int j = 0; j < W; ++j) R[i * W + j] = j < count ? row[j] : 0.0;
    }
    return;
  }
  const int rows = n - n % kLanes, columns = count - count % kLanes;
  for (int i = 0; i < rows; i += kLanes) {
    for (int j = 0; j < columns; j += kLanes)
      turn_block(B.in + i + (j0 + j) * B.column_step, B.column_step, R + i * W + j, W);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i < rows ? columns : 0; j < W; ++j)
      R[i * W + j] = j < count ? B.in[i + (j0 + j) * B.column_step] : 0.0;
  }
}

// The tile's first count columns into X's columns j0 .. (column-major), in turned blocks.
template <int W>
void copy_out(int n, const double* __restrict R, const RightHandSides& B, int j0, int count) {
  const int rows = n - n % kLanes, columns = count - count % kLanes;
  for (int i = 0; i < rows; i += kLanes) {
    for (int j = 0; j < columns; j += kLanes)
      turn_block(R + i * W + j, W, B.out + i + (j0 + j) * n, n);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i < rows ? columns : 0; j < count; ++j) B.out[i + (j0 + j) * n] = R[i * W + j];
  }
}

// `count` <= V·kLanes columns of B from column j0, copied row by row into R,
// solved forward then backward in blocks of kRows rows, and copied to X.
template <int V>
void solve_tile(int n, const double* __restrict L, const RightHandSides& B, int j0, int count,
                double sign, double* __restrict R) {
  constexpr int W = V * kLanes;
  copy_in<W>(n, B, j0, count, R);
  int i = 0;
  for (; i + kRows <= n; i += kRows) solve_rows<kRows, V, true>(n, L, R, i, sign);
  for (; i < n; ++i) solve_rows<1, V, true>(n, L, R, i, sign);
  i = n - 1;
  for (; i + 1 >= kRows; i -= kRows) solve_rows<kRows, V, false>(n, L, R, i, 1.0);
  for (; i >= 0; --i) solve_rows<1, V, false>(n, L, R, i, 1.0);
  copy_out<W>(n, R, B, j0, count);
}

// The last `rest` columns (fewer than kTile) in one tile of the fewest vectors that hold them.
template <int V = 1>
void solve_rest(int n, const double* L, const RightHandSides& B, int j0, int rest, double sign,
                double* R) {
  if constexpr (V < kVectors) {
    if (rest > V * kLanes) return solve_rest<V + 1>(n, L, B, j0, rest, sign, R);
  }
  solve_tile<V>(n, L, B, j0, rest, sign, R);
}

// Tiles of kTile columns, then the rest.
void solve(int n, const double* L, RightHandSides B, bool negate, double* R) {
  const double sign = negate ? -1.0 : 1.0;
  int j = 0;
  for (; j + kTile <= B.m; j += kTile) solve_tile<kVectors>(n, L, B, j, kTile, sign, R);
  if (j < B.m) solve_rest(n, L, B, j, B.m - j, sign, R);
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
// L_jj = sqrt(M_jj - Σ_k<j L_jk²), rows in chunks of kFactorRows (then 8, 4, 1). ratio: min_j
// D_j / M_jj (D_j = L_jj²); false at the first D_j not > 0 (NaN too), ratio then D_j / M_jj
// where D_j < 0 < M_jj, else 0.
bool factor(int n, const double* __restrict M, double* __restrict L, double* ratio) {
  double smallest = 1.0;
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) L[i + j * n] = M[i + j * n];
    int i = j;
    for (; i + kFactorRows <= n; i += kFactorRows) subtract_columns_before<kFactorRows>(n, j, i, L);
    if constexpr (kFactorRows > 8) {
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

const DenseKernels kernels{kName, solve, factor};
