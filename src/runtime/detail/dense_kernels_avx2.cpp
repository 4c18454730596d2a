// The dense kernels compiled for AVX2 with FMA (this file alone: -mavx2 -mfma
// -ffp-contract=off, src/runtime/CMakeLists.txt: fused only where
// multiply_subtract says so), called only where the processor runs them
// (wide_dense_kernels()). It includes nothing but the kernels' own header and
// <climits> (macros), so that no inline function of a library is compiled
// here for AVX2.

#include <climits>

#include <symdyn/runtime/detail/dense_kernels.hpp>

namespace symdyn::runtime::detail::avx2 {

constexpr int kTile = 32;
constexpr int kTilesUpTo = INT_MAX;
constexpr const char* kName = "avx2";
inline double multiply_subtract(double a, double b, double c) {
  return __builtin_fma(-b, c, a);
}
extern const DenseKernels kernels;
#include "dense_kernels_body.hpp"

}  // namespace symdyn::runtime::detail::avx2
