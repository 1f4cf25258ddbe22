#include "gesture/nn/batch.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace deixis::nn {
namespace {

// A block of R rows × (8·V) columns: R·V accumulators stay in registers over the whole depth
// (6 × 2 = 12 of AVX2's 16), each weight vector is loaded once and used R times.
#if defined(__AVX2__) && defined(__FMA__)
template <int R, int V>
void block(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
           std::size_t ldc, int depth) noexcept {
  __m256 acc[R][V];
  for (int r = 0; r < R; ++r) {
    for (int v = 0; v < V; ++v) {
      acc[r][v] = _mm256_setzero_ps();
    }
  }
  for (int i = 0; i < depth; ++i) {
    __m256 wv[V];
    for (int v = 0; v < V; ++v) {
      wv[v] = _mm256_loadu_ps(w + static_cast<std::size_t>(i) * ldw + 8 * v);
    }
    for (int r = 0; r < R; ++r) {
      const __m256 x = _mm256_broadcast_ss(a + static_cast<std::size_t>(r) * lda + i);
      for (int v = 0; v < V; ++v) {
        acc[r][v] = _mm256_fmadd_ps(x, wv[v], acc[r][v]);
      }
    }
  }
  for (int r = 0; r < R; ++r) {
    for (int v = 0; v < V; ++v) {
      _mm256_storeu_ps(c + static_cast<std::size_t>(r) * ldc + 8 * v, acc[r][v]);
    }
  }
}

template <int V>
void column_block(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                  std::size_t ldc, int rows, int depth) noexcept {
  constexpr int kRows = 6;
  int r = 0;
  for (; r + kRows <= rows; r += kRows) {
    block<kRows, V>(a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth);
  }
  // The remaining 1 to 5 rows in one narrower block.
  using Block = void (*)(const float*, std::size_t, const float*, std::size_t, float*, std::size_t,
                         int) noexcept;
  static constexpr Block kNarrower[kRows] = {nullptr,     block<1, V>, block<2, V>,
                                             block<3, V>, block<4, V>, block<5, V>};
  if (r < rows) {
    kNarrower[rows - r](a + r * lda, lda, w, ldw, c + r * ldc, ldc, depth);
  }
}
#endif

// Columns [from, to) one value at a time (narrow remainders, and builds without AVX2).
void scalar_columns(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                    std::size_t ldc, int rows, int depth, int from, int to) noexcept {
  for (int r = 0; r < rows; ++r) {
    const float* ar = a + static_cast<std::size_t>(r) * lda;
    for (int j = from; j < to; ++j) {
      float sum = 0.0f;
      for (int i = 0; i < depth; ++i) {
        sum += ar[i] * w[static_cast<std::size_t>(i) * ldw + j];
      }
      c[static_cast<std::size_t>(r) * ldc + j] = sum;
    }
  }
}

}  // namespace

void multiply_rows(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                   std::size_t ldc, int rows, int depth, int cols) noexcept {
  int j = 0;
#if defined(__AVX2__) && defined(__FMA__)
  if (rows == 1) {
    // One person (the networks' run()): six independent accumulator chains instead of two, so
    // the products are not bound by the FMA latency. Same sums, same order.
    for (; j + 48 <= cols; j += 48) {
      block<1, 6>(a, lda, w + j, ldw, c + j, ldc, depth);
    }
  }
  for (; j + 16 <= cols; j += 16) {
    column_block<2>(a, lda, w + j, ldw, c + j, ldc, rows, depth);
  }
  for (; j + 8 <= cols; j += 8) {
    column_block<1>(a, lda, w + j, ldw, c + j, ldc, rows, depth);
  }
#endif
  scalar_columns(a, lda, w, ldw, c, ldc, rows, depth, j, cols);
}

}  // namespace deixis::nn
