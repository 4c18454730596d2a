// The dense kernels compiled for AVX2 with FMA (this file alone: -mavx2 -mfma
// -ffp-contract=off, src/runtime/CMakeLists.txt: fused only where
// multiply_subtract says so), called only where the processor runs them
// (wide_dense_kernels()). It includes nothing but the kernels' own header and
// the intrinsics' (always inlined, never an out-of-line definition), so that no
// inline function of a library is compiled here for AVX2.

#include <immintrin.h>

#include <symdyn/runtime/detail/dense_kernels.hpp>

namespace symdyn::runtime::detail::avx2 {

constexpr const char* kName = "avx2";
constexpr int kLanes = 4;
typedef double Vector __attribute__((vector_size(kLanes * sizeof(double))));
inline Vector multiply_subtract(Vector a, double b, Vector c) {
  return _mm256_fnmadd_pd(_mm256_set1_pd(b), c, a);
}
constexpr int kFactorRows = 16;
extern const DenseKernels kernels;
#include "dense_kernels_body.hpp"

}  // namespace symdyn::runtime::detail::avx2
