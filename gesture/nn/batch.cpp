#include "gesture/nn/batch.h"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "gesture/nn/simd_target.h"

#if (defined(__AVX2__) && defined(__FMA__)) || DEIXIS_AVX512_KERNEL
#include <immintrin.h>
#endif

namespace deixis::nn {
namespace {

// A block of R ≤ 6 rows × 16 columns: R·2 accumulators stay in registers over the whole depth,
// each weight vector is loaded once and used R times. The accumulators are named variables, not
// an array: GCC 12 keeps an array of __m256 on the stack and stores it on every iteration, which
// halved the speed (64 × 264 by 264 × 1296: 24 against 45 GFMA/s of CPU time, measured).
#if defined(__AVX2__) && defined(__FMA__)
template <int R>
void block16(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
             std::size_t ldc, int depth) noexcept {
  __m256 c00 = _mm256_setzero_ps(), c01 = c00, c10 = c00, c11 = c00, c20 = c00, c21 = c00;
  __m256 c30 = c00, c31 = c00, c40 = c00, c41 = c00, c50 = c00, c51 = c00;
  const float* a1 = a + lda;
  const float* a2 = a1 + lda;
  const float* a3 = a2 + lda;
  const float* a4 = a3 + lda;
  const float* a5 = a4 + lda;
  for (int i = 0; i < depth; ++i) {
    const __m256 w0 = _mm256_loadu_ps(w);
    const __m256 w1 = _mm256_loadu_ps(w + 8);
    w += ldw;
    __m256 x = _mm256_broadcast_ss(a + i);
    c00 = _mm256_fmadd_ps(x, w0, c00);
    c01 = _mm256_fmadd_ps(x, w1, c01);
    if constexpr (R > 1) {
      x = _mm256_broadcast_ss(a1 + i);
      c10 = _mm256_fmadd_ps(x, w0, c10);
      c11 = _mm256_fmadd_ps(x, w1, c11);
    }
    if constexpr (R > 2) {
      x = _mm256_broadcast_ss(a2 + i);
      c20 = _mm256_fmadd_ps(x, w0, c20);
      c21 = _mm256_fmadd_ps(x, w1, c21);
    }
    if constexpr (R > 3) {
      x = _mm256_broadcast_ss(a3 + i);
      c30 = _mm256_fmadd_ps(x, w0, c30);
      c31 = _mm256_fmadd_ps(x, w1, c31);
    }
    if constexpr (R > 4) {
      x = _mm256_broadcast_ss(a4 + i);
      c40 = _mm256_fmadd_ps(x, w0, c40);
      c41 = _mm256_fmadd_ps(x, w1, c41);
    }
    if constexpr (R > 5) {
      x = _mm256_broadcast_ss(a5 + i);
      c50 = _mm256_fmadd_ps(x, w0, c50);
      c51 = _mm256_fmadd_ps(x, w1, c51);
    }
  }
  const __m256 out[6][2] = {{c00, c01}, {c10, c11}, {c20, c21}, {c30, c31}, {c40, c41}, {c50, c51}};
  for (int r = 0; r < R; ++r) {
    _mm256_storeu_ps(c + r * ldc, out[r][0]);
    _mm256_storeu_ps(c + r * ldc + 8, out[r][1]);
  }
}

// One row × 48 columns (a person alone): six independent chains, so the product is not bound by
// the FMA latency. The same sums in the same order as block16.
void row48(const float* a, const float* w, std::size_t ldw, float* c, int depth) noexcept {
  __m256 c0 = _mm256_setzero_ps(), c1 = c0, c2 = c0, c3 = c0, c4 = c0, c5 = c0;
  for (int i = 0; i < depth; ++i) {
    const __m256 x = _mm256_broadcast_ss(a + i);
    c0 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w), c0);
    c1 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w + 8), c1);
    c2 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w + 16), c2);
    c3 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w + 24), c3);
    c4 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w + 32), c4);
    c5 = _mm256_fmadd_ps(x, _mm256_loadu_ps(w + 40), c5);
    w += ldw;
  }
  _mm256_storeu_ps(c, c0);
  _mm256_storeu_ps(c + 8, c1);
  _mm256_storeu_ps(c + 16, c2);
  _mm256_storeu_ps(c + 24, c3);
  _mm256_storeu_ps(c + 32, c4);
  _mm256_storeu_ps(c + 40, c5);
}

// 16 columns of every row, six rows at a time.
void column_block16(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                    std::size_t ldc, int rows, int depth) noexcept {
  constexpr int kRows = 6;
  int r = 0;
  for (; r + kRows <= rows; r += kRows) {
    block16<kRows>(a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth);
  }
  // The remaining 1 to 5 rows in one narrower block.
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int) noexcept;
  static constexpr Block kNarrower[kRows] = {nullptr,    block16<1>, block16<2>,
                                             block16<3>, block16<4>, block16<5>};
  if (r < rows) {
    kNarrower[rows - r](a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth);
  }
}

// A block of R ≤ 12 rows × one vector of up to eight columns (a layer's last 8 or fewer, e.g.
// UGNet's third expert layer, 24 columns a panel). Every row is its own chain of multiply-adds, so
// R chains run at once: a row at a time, each multiply-add waited on the one before (4 cycles),
// ran at a tenth of the peak and took 1.2 µs a person at 64 on the Xeon (docs/scaling.md). With
// fewer than eight columns (`Masked`), masked loads read zeros beyond `mask` and masked stores
// leave those columns alone; every lane is the same fused chain as the scalar code's, so the bits
// are the same.
template <int R, bool Masked, std::size_t... K>
inline void block8(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                   std::size_t ldc, int depth, __m256i mask, std::index_sequence<K...>) noexcept {
  __m256 acc[R];
  ((acc[K] = _mm256_setzero_ps()), ...);
  for (int i = 0; i < depth; ++i) {
    const __m256 wv = Masked ? _mm256_maskload_ps(w, mask) : _mm256_loadu_ps(w);
    w += ldw;
    ((acc[K] = _mm256_fmadd_ps(_mm256_broadcast_ss(a + K * lda + i), wv, acc[K])), ...);
  }
  if constexpr (Masked) {
    (_mm256_maskstore_ps(c + K * ldc, mask, acc[K]), ...);
  } else {
    (_mm256_storeu_ps(c + K * ldc, acc[K]), ...);
  }
}

template <int R, bool Masked>
void block8(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
            std::size_t ldc, int depth, __m256i mask) noexcept {
  block8<R, Masked>(a, lda, w, ldw, c, ldc, depth, mask,
                    std::make_index_sequence<static_cast<std::size_t>(R)>{});
}

// Up to eight columns (`width`) of every row, twelve rows at a time.
template <bool Masked>
void column_block8(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                   std::size_t ldc, int rows, int depth, int width) noexcept {
  const __m256i mask =
      _mm256_cmpgt_epi32(_mm256_set1_epi32(width), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  constexpr int kRows = 12;
  int r = 0;
  for (; r + kRows <= rows; r += kRows) {
    block8<kRows, Masked>(a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth, mask);
  }
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int, __m256i) noexcept;
  static constexpr Block kNarrower[kRows] = {
      nullptr,           block8<1, Masked>, block8<2, Masked>,  block8<3, Masked>,
      block8<4, Masked>, block8<5, Masked>, block8<6, Masked>,  block8<7, Masked>,
      block8<8, Masked>, block8<9, Masked>, block8<10, Masked>, block8<11, Masked>};
  if (r < rows) {
    kNarrower[rows - r](a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth, mask);
  }
}

// People in lanes (multiply_lanes): R ≤ 6 output rows × V ≤ 2 vectors of eight people. The
// accumulators are an array indexed only through pack expansions, as zblock's below, so they stay
// in registers.
template <int R, int V, std::size_t... P, std::size_t... K>
inline void lane_block8(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                        std::size_t ldc, int depth, const float* bias, std::index_sequence<P...>,
                        std::index_sequence<K...>) noexcept {
  __m256 acc[R * V];
  ((acc[K] = _mm256_setzero_ps()), ...);
  for (int i = 0; i < depth; ++i) {
    __m256 xv[V];
    ((xv[P] = _mm256_loadu_ps(x + 8 * P)), ...);
    x += ldx;
    ((acc[K] = _mm256_fmadd_ps(_mm256_broadcast_ss(w + (K / V) * ldw + i), xv[K % V], acc[K])),
     ...);
  }
  if (bias != nullptr) {
    ((acc[K] = _mm256_add_ps(acc[K], _mm256_broadcast_ss(bias + K / V))), ...);
  }
  (_mm256_storeu_ps(c + (K / V) * ldc + 8 * (K % V), acc[K]), ...);
}

template <int R>
void lane_block8(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                 std::size_t ldc, int depth, const float* bias) noexcept {
  lane_block8<R, 2>(w, ldw, x, ldx, c, ldc, depth, bias, std::make_index_sequence<2>{},
                    std::make_index_sequence<static_cast<std::size_t>(R * 2)>{});
}

void multiply_lanes_avx2(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                         std::size_t ldc, int rows, int depth, int lanes,
                         const float* bias) noexcept {
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int, const float*) noexcept;
  static constexpr Block kNarrower[6] = {nullptr,        lane_block8<1>, lane_block8<2>,
                                         lane_block8<3>, lane_block8<4>, lane_block8<5>};
  const auto row_bias = [bias](int j) { return bias == nullptr ? nullptr : bias + j; };
  for (int p = 0; p < lanes; p += 16) {
    int j = 0;
    for (; j + 6 <= rows; j += 6) {
      lane_block8<6>(w + j * ldw, ldw, x + p, ldx, c + j * ldc + p, ldc, depth, row_bias(j));
    }
    if (j < rows) {
      kNarrower[rows - j](w + j * ldw, ldw, x + p, ldx, c + j * ldc + p, ldc, depth, row_bias(j));
    }
  }
}
#endif

#if DEIXIS_AVX512_KERNEL
// The same products with AVX-512, chosen at run time where the CPU has it (the build stays
// x86-64-v3; docs/scaling.md). A block is R ≤ 8 rows × Z ≤ 3 vectors of 16 columns, so up to 24
// accumulators of the 32 registers. Each lane is the same fmadd chain over i in the same order as
// the AVX2 kernels', so the bits are the same whichever kernel runs (the AVX2 build's narrow
// remainders are the same fused multiply-adds, in masked vectors of eight). The accumulators
// are an array indexed only through pack expansions (no loop over them), so the compiler can keep
// them in registers (batch_test's kernel comparison and translator_bench's BM_BatchProduct say
// whether it did).
template <int R, int Z, std::size_t... V, std::size_t... K>
DEIXIS_AVX512_TARGET inline void zblock(const float* a, std::size_t lda, const float* w,
                                        std::size_t ldw, float* c, std::size_t ldc, int depth,
                                        __mmask16 last, std::index_sequence<V...>,
                                        std::index_sequence<K...>) noexcept {
  // Accumulator K holds row K / Z, columns [16·(K % Z), 16·(K % Z) + 16); of the last vector
  // only the columns in `last` are read and written.
  constexpr auto mask = [](std::size_t v, __mmask16 last_mask) {
    return v + 1 == Z ? last_mask : static_cast<__mmask16>(0xffff);
  };
  __m512 acc[R * Z];
  ((acc[K] = _mm512_setzero_ps()), ...);
  for (int i = 0; i < depth; ++i) {
    __m512 wv[Z];
    ((wv[V] = _mm512_maskz_loadu_ps(mask(V, last), w + 16 * V)), ...);
    w += ldw;
    ((acc[K] = _mm512_fmadd_ps(_mm512_set1_ps(a[(K / Z) * lda + i]), wv[K % Z], acc[K])), ...);
  }
  (_mm512_mask_storeu_ps(c + (K / Z) * ldc + 16 * (K % Z), mask(K % Z, last), acc[K]), ...);
}

template <int R, int Z>
DEIXIS_AVX512_TARGET void zblock(const float* a, std::size_t lda, const float* w, std::size_t ldw,
                                 float* c, std::size_t ldc, int depth, __mmask16 last) noexcept {
  zblock<R, Z>(a, lda, w, ldw, c, ldc, depth, last, std::make_index_sequence<Z>{},
               std::make_index_sequence<static_cast<std::size_t>(R * Z)>{});
}

// Z vectors of 16 columns of every row (the last one's columns as `last` says), eight rows at a
// time.
template <int Z>
DEIXIS_AVX512_TARGET void column_zblock(const float* a, std::size_t lda, const float* w,
                                        std::size_t ldw, float* c, std::size_t ldc, int rows,
                                        int depth, __mmask16 last) noexcept {
  constexpr int kRows = 8;
  int r = 0;
  for (; r + kRows <= rows; r += kRows) {
    zblock<kRows, Z>(a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth, last);
  }
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int, __mmask16) noexcept;
  static constexpr Block kNarrower[kRows] = {nullptr,      zblock<1, Z>, zblock<2, Z>,
                                             zblock<3, Z>, zblock<4, Z>, zblock<5, Z>,
                                             zblock<6, Z>, zblock<7, Z>};
  if (r < rows) {
    kNarrower[rows - r](a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth, last);
  }
}

// Every column: groups of 48, then the rest (1 to 47 columns) as one group of up to three
// vectors, the last masked, so that no row is ever done alone or a column one value at a time.
DEIXIS_AVX512_TARGET void multiply_rows_avx512(const float* a, std::size_t lda, const float* w,
                                               std::size_t ldw, float* c, std::size_t ldc, int rows,
                                               int depth, int cols) noexcept {
  constexpr __mmask16 kFull = 0xffff;
  int j = 0;
  for (; j + 48 <= cols; j += 48) {
    column_zblock<3>(a, lda, w + j, ldw, c + j, ldc, rows, depth, kFull);
  }
  const int rest = cols - j;
  if (rest == 0) {
    return;
  }
  const int tail = rest - 16 * ((rest - 1) / 16);  // 1 to 16 columns in the last vector
  const auto last = static_cast<__mmask16>(tail == 16 ? kFull : (1u << tail) - 1u);
  if (rest > 32) {
    column_zblock<3>(a, lda, w + j, ldw, c + j, ldc, rows, depth, last);
  } else if (rest > 16) {
    column_zblock<2>(a, lda, w + j, ldw, c + j, ldc, rows, depth, last);
  } else {
    column_zblock<1>(a, lda, w + j, ldw, c + j, ldc, rows, depth, last);
  }
}

// People in lanes (multiply_lanes): R ≤ 6 output rows × V ≤ 4 vectors of sixteen people, up to 24
// accumulators.
template <int R, int V, std::size_t... P, std::size_t... K>
DEIXIS_AVX512_TARGET inline void lane_block16(const float* w, std::size_t ldw, const float* x,
                                              std::size_t ldx, float* c, std::size_t ldc, int depth,
                                              const float* bias, std::index_sequence<P...>,
                                              std::index_sequence<K...>) noexcept {
  __m512 acc[R * V];
  ((acc[K] = _mm512_setzero_ps()), ...);
  for (int i = 0; i < depth; ++i) {
    __m512 xv[V];
    ((xv[P] = _mm512_loadu_ps(x + 16 * P)), ...);
    x += ldx;
    ((acc[K] = _mm512_fmadd_ps(_mm512_set1_ps(w[(K / V) * ldw + i]), xv[K % V], acc[K])), ...);
  }
  if (bias != nullptr) {
    ((acc[K] = _mm512_add_ps(acc[K], _mm512_set1_ps(bias[K / V]))), ...);
  }
  (_mm512_storeu_ps(c + (K / V) * ldc + 16 * (K % V), acc[K]), ...);
}

template <int R, int V>
DEIXIS_AVX512_TARGET void lane_block16(const float* w, std::size_t ldw, const float* x,
                                       std::size_t ldx, float* c, std::size_t ldc, int depth,
                                       const float* bias) noexcept {
  lane_block16<R, V>(w, ldw, x, ldx, c, ldc, depth, bias, std::make_index_sequence<V>{},
                     std::make_index_sequence<static_cast<std::size_t>(R * V)>{});
}

// Every output row, six at a time, for V vectors of people starting at lane 0.
template <int V>
DEIXIS_AVX512_TARGET void lane_rows16(const float* w, std::size_t ldw, const float* x,
                                      std::size_t ldx, float* c, std::size_t ldc, int rows,
                                      int depth, const float* bias) noexcept {
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int, const float*) noexcept;
  static constexpr Block kNarrower[6] = {nullptr,
                                         lane_block16<1, V>,
                                         lane_block16<2, V>,
                                         lane_block16<3, V>,
                                         lane_block16<4, V>,
                                         lane_block16<5, V>};
  const auto row_bias = [bias](int j) { return bias == nullptr ? nullptr : bias + j; };
  int j = 0;
  for (; j + 6 <= rows; j += 6) {
    lane_block16<6, V>(w + j * ldw, ldw, x, ldx, c + j * ldc, ldc, depth, row_bias(j));
  }
  if (j < rows) {
    kNarrower[rows - j](w + j * ldw, ldw, x, ldx, c + j * ldc, ldc, depth, row_bias(j));
  }
}

// Lanes 64 at a time, then the last 16, 32 or 48.
DEIXIS_AVX512_TARGET void multiply_lanes_avx512(const float* w, std::size_t ldw, const float* x,
                                                std::size_t ldx, float* c, std::size_t ldc,
                                                int rows, int depth, int lanes,
                                                const float* bias) noexcept {
  int p = 0;
  for (; p + 64 <= lanes; p += 64) {
    lane_rows16<4>(w, ldw, x + p, ldx, c + p, ldc, rows, depth, bias);
  }
  switch ((lanes - p) / 16) {
    case 3:
      lane_rows16<3>(w, ldw, x + p, ldx, c + p, ldc, rows, depth, bias);
      break;
    case 2:
      lane_rows16<2>(w, ldw, x + p, ldx, c + p, ldc, rows, depth, bias);
      break;
    case 1:
      lane_rows16<1>(w, ldw, x + p, ldx, c + p, ldc, rows, depth, bias);
      break;
    default:
      break;
  }
}
#endif

#if !(defined(__AVX2__) && defined(__FMA__))
// Columns [from, to) one value at a time (builds without AVX2).
void scalar_columns(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                    std::size_t ldc, int rows, int depth, int from, int to) noexcept {
  for (int r = 0; r < rows; ++r) {
    const float* ar = a + static_cast<std::size_t>(r) * lda;
    for (int j = from; j < to; ++j) {
      float sum = 0.0f;
      for (int i = 0; i < depth; ++i) {
#if defined(__FMA__)
        // Fused, as every lane of the vector kernels is, so a column's bits do not depend on
        // which kernel reached it.
        sum = std::fma(ar[i], w[static_cast<std::size_t>(i) * ldw + j], sum);
#else
        sum += ar[i] * w[static_cast<std::size_t>(i) * ldw + j];
#endif
      }
      c[static_cast<std::size_t>(r) * ldc + j] = sum;
    }
  }
}

#endif

// `kernel` is available here (the callers below make sure).
void multiply(ProductKernel kernel, const float* a, std::size_t lda, const float* w,
              std::size_t ldw, float* c, std::size_t ldc, int rows, int depth, int cols) noexcept {
#if DEIXIS_AVX512_KERNEL
  if (kernel == ProductKernel::kAvx512) {
    multiply_rows_avx512(a, lda, w, ldw, c, ldc, rows, depth, cols);
    return;
  }
#else
  (void)kernel;
#endif
  int j = 0;
#if defined(__AVX2__) && defined(__FMA__)
  if (rows == 1) {
    for (; j + 48 <= cols; j += 48) {
      row48(a, w + j, ldw, c + j, depth);
    }
  }
  for (; j + 16 <= cols; j += 16) {
    column_block16(a, lda, w + j, ldw, c + j, ldc, rows, depth);
  }
  if (j + 8 <= cols) {
    column_block8<false>(a, lda, w + j, ldw, c + j, ldc, rows, depth, 8);
    j += 8;
  }
  if (j < cols) {
    column_block8<true>(a, lda, w + j, ldw, c + j, ldc, rows, depth, cols - j);
  }
#else
  scalar_columns(a, lda, w, ldw, c, ldc, rows, depth, j, cols);
#endif
}

#if !(defined(__AVX2__) && defined(__FMA__))
// People in lanes one value at a time (builds without AVX2): the same chains as scalar_columns.
void scalar_lanes(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                  std::size_t ldc, int rows, int depth, int lanes, const float* bias) noexcept {
  for (int j = 0; j < rows; ++j) {
    const float* wj = w + static_cast<std::size_t>(j) * ldw;
    float* cj = c + static_cast<std::size_t>(j) * ldc;
    for (int p = 0; p < lanes; ++p) {
      float sum = 0.0f;
      for (int i = 0; i < depth; ++i) {
#if defined(__FMA__)
        sum = std::fma(x[static_cast<std::size_t>(i) * ldx + p], wj[i], sum);
#else
        sum += x[static_cast<std::size_t>(i) * ldx + p] * wj[i];
#endif
      }
      cj[p] = bias == nullptr ? sum : sum + bias[j];
    }
  }
}
#endif

// `kernel` is available here (the callers below make sure).
void multiply_in_lanes(ProductKernel kernel, const float* w, std::size_t ldw, const float* x,
                       std::size_t ldx, float* c, std::size_t ldc, int rows, int depth, int lanes,
                       const float* bias) noexcept {
#if DEIXIS_AVX512_KERNEL
  if (kernel == ProductKernel::kAvx512) {
    multiply_lanes_avx512(w, ldw, x, ldx, c, ldc, rows, depth, lanes, bias);
    return;
  }
#else
  (void)kernel;
#endif
#if defined(__AVX2__) && defined(__FMA__)
  multiply_lanes_avx2(w, ldw, x, ldx, c, ldc, rows, depth, lanes, bias);
#else
  scalar_lanes(w, ldw, x, ldx, c, ldc, rows, depth, lanes, bias);
#endif
}

}  // namespace

bool product_kernel_available(ProductKernel kernel) noexcept {
  switch (kernel) {
    case ProductKernel::kBuild:
      return true;
    case ProductKernel::kAvx512:
#if DEIXIS_AVX512_KERNEL
      return __builtin_cpu_supports("avx512f") != 0;
#else
      return false;
#endif
  }
  return false;
}

namespace {

// DEIXIS_PRODUCT_KERNEL=build keeps a CPU with AVX-512 to the build's kernels, so that the figures
// of a CPU without it can be measured on one with it (as oneDNN's ONEDNN_MAX_CPU_ISA does). Both
// kernels give the same bits; only speed differs. Read once: the choice must not change between
// calls of one run.
ProductKernel choose_product_kernel() noexcept {
  const bool avx512 = product_kernel_available(ProductKernel::kAvx512);
  const ProductKernel best = avx512 ? ProductKernel::kAvx512 : ProductKernel::kBuild;
  const char* asked = std::getenv("DEIXIS_PRODUCT_KERNEL");
  if (asked == nullptr || *asked == '\0' || std::strcmp(asked, "best") == 0) {
    return best;
  }
  if (std::strcmp(asked, "build") == 0) {
    return ProductKernel::kBuild;
  }
  const bool asks_avx512 = std::strcmp(asked, "avx512") == 0;
  if (asks_avx512 && avx512) {
    return ProductKernel::kAvx512;
  }
  std::fprintf(stderr, "deixis: DEIXIS_PRODUCT_KERNEL=%s %s; using the %s kernels\n", asked,
               asks_avx512 ? "asks for AVX-512, which this CPU or build lacks"
                           : "is not one of best, build, avx512",
               avx512 ? "AVX-512" : "build's");
  return best;
}

}  // namespace

ProductKernel best_product_kernel() noexcept {
  static const ProductKernel chosen = choose_product_kernel();
  return chosen;
}

void multiply_rows(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                   std::size_t ldc, int rows, int depth, int cols) noexcept {
  multiply(best_product_kernel(), a, lda, w, ldw, c, ldc, rows, depth, cols);
}

void multiply_rows(ProductKernel kernel, const float* a, std::size_t lda, const float* w,
                   std::size_t ldw, float* c, std::size_t ldc, int rows, int depth,
                   int cols) noexcept {
  // Asked for where the CPU lacks it, the build's kernels answer (an illegal instruction would
  // not).
  multiply(product_kernel_available(kernel) ? kernel : ProductKernel::kBuild, a, lda, w, ldw, c,
           ldc, rows, depth, cols);
}

void multiply_lanes(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                    std::size_t ldc, int rows, int depth, int lanes, const float* bias) noexcept {
  multiply_in_lanes(best_product_kernel(), w, ldw, x, ldx, c, ldc, rows, depth, lanes, bias);
}

void multiply_lanes(ProductKernel kernel, const float* w, std::size_t ldw, const float* x,
                    std::size_t ldx, float* c, std::size_t ldc, int rows, int depth, int lanes,
                    const float* bias) noexcept {
  multiply_in_lanes(product_kernel_available(kernel) ? kernel : ProductKernel::kBuild, w, ldw, x,
                    ldx, c, ldc, rows, depth, lanes, bias);
}

#if DEIXIS_AVX512_KERNEL
namespace {

// Sixteen people's value of one column in one gather: a person's row is contiguous in their
// window, so the scalar loop below stores one value at a time `count` floats apart.
DEIXIS_AVX512_TARGET void window_row_to_lanes_avx512(const float* windows, std::size_t window_size,
                                                     std::size_t row, int columns, int count,
                                                     float* x) noexcept {
  const auto ld = static_cast<std::size_t>(count);
  const __m512i person =
      _mm512_mullo_epi32(_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
                         _mm512_set1_epi32(static_cast<int>(window_size)));
  for (int p = 0; p < count; p += kLaneGroup) {
    const float* first = windows + static_cast<std::size_t>(p) * window_size + row;
    for (int c = 0; c < columns; ++c) {
      _mm512_storeu_ps(x + static_cast<std::size_t>(c) * ld + static_cast<std::size_t>(p),
                       _mm512_mask_i32gather_ps(_mm512_setzero_ps(), 0xffff, person, first + c, 4));
    }
  }
}

}  // namespace
#endif

void window_row_to_lanes(const float* windows, std::size_t window_size, std::size_t row,
                         int columns, int count, float* x) noexcept {
#if DEIXIS_AVX512_KERNEL
  // Whole groups of sixteen, and window offsets the gather's 32-bit indices hold (always).
  if (count % kLaneGroup == 0 && window_size < (std::size_t{1} << 26) &&
      best_product_kernel() == ProductKernel::kAvx512) {
    window_row_to_lanes_avx512(windows, window_size, row, columns, count, x);
    return;
  }
#endif
  const auto ld = static_cast<std::size_t>(count);
  for (int p = 0; p < count; ++p) {
    const float* in = windows + static_cast<std::size_t>(p) * window_size + row;
    for (int c = 0; c < columns; ++c) {
      x[static_cast<std::size_t>(c) * ld + static_cast<std::size_t>(p)] = in[c];
    }
  }
}

void lanes_to_rows(const float* v, int size, int count, int lanes, float* out) noexcept {
  for (int r = 0; r < count; ++r) {
    for (int j = 0; j < size; ++j) {
      out[static_cast<std::size_t>(r) * size + j] = v[static_cast<std::size_t>(j) * lanes + r];
    }
  }
}

}  // namespace deixis::nn
