#include <symdyn/runtime/detail/dense_kernels.hpp>

namespace symdyn::runtime::detail {

namespace plain {
constexpr const char* kName = "plain";
constexpr int kLanes = 2;  // SSE2, the x86-64 baseline (elsewhere what the compiler makes of it)
typedef double Vector __attribute__((vector_size(kLanes * sizeof(double))));
inline Vector multiply_subtract(Vector a, double b, Vector c) {
  return a - b * c;
}
constexpr int kFactorRows = 8;
#include "dense_kernels_body.hpp"
}  // namespace plain

#if SYMDYN_WIDE_KERNELS
namespace avx2 {
extern const DenseKernels kernels;  // dense_kernels_avx2.cpp
}
#endif

const DenseKernels& plain_dense_kernels() {
  return plain::kernels;
}

const DenseKernels* wide_dense_kernels() {
#if SYMDYN_WIDE_KERNELS
  static const bool runs = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return runs ? &avx2::kernels : nullptr;
#else
  return nullptr;
#endif
}

}  // namespace symdyn::runtime::detail
