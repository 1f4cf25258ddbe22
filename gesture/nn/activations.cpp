#include "gesture/nn/activations.h"

#include "gesture/nn/simd_target.h"

namespace deixis::nn {
namespace {

void elu_loop(float* x, std::size_t count) noexcept {
  for (std::size_t i = 0; i < count; ++i) {
    x[i] = elu(x[i]);
  }
}

// GCC takes the vector width in the target attribute; Clang does not (its loop stays the build's).
#if DEIXIS_AVX512_KERNEL && !defined(__clang__)
#define DEIXIS_AVX512_ELU 1
#else
#define DEIXIS_AVX512_ELU 0
#endif

#if DEIXIS_AVX512_ELU
// The same loop compiled for AVX-512 with 16-float vectors (GCC otherwise keeps 8-float ones even
// for that target). Every value still goes through elu()'s fixed sequence of IEEE
// operations, each lane on its own, so the bits are the same as the build's loop (decision 88;
// tests/nn/lanewise_math_test.cpp compares the two).
__attribute__((target("avx512f,prefer-vector-width=512"))) void elu_loop_avx512(
    float* x, std::size_t count) noexcept {
  for (std::size_t i = 0; i < count; ++i) {
    x[i] = elu(x[i]);
  }
}
#endif

}  // namespace

void elu_inplace(ProductKernel kernel, float* x, std::size_t count) noexcept {
#if DEIXIS_AVX512_ELU
  if (kernel == ProductKernel::kAvx512) {
    elu_loop_avx512(x, count);
    return;
  }
#else
  (void)kernel;
#endif
  elu_loop(x, count);
}

void elu_inplace(float* x, std::size_t count) noexcept {
  elu_inplace(best_product_kernel(), x, count);
}

}  // namespace deixis::nn
