#include "gesture/nn/batch.h"

#if defined(__AVX2__) && defined(__FMA__)
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

// Eight columns, one row (narrow remainders).
void row8(const float* a, const float* w, std::size_t ldw, float* c, int depth) noexcept {
  __m256 c0 = _mm256_setzero_ps();
  for (int i = 0; i < depth; ++i) {
    c0 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + i), _mm256_loadu_ps(w), c0);
    w += ldw;
  }
  _mm256_storeu_ps(c, c0);
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
    for (; j + 48 <= cols; j += 48) {
      row48(a, w + j, ldw, c + j, depth);
    }
  }
  for (; j + 16 <= cols; j += 16) {
    column_block16(a, lda, w + j, ldw, c + j, ldc, rows, depth);
  }
  for (; j + 8 <= cols; j += 8) {
    for (int r = 0; r < rows; ++r) {
      row8(a + r * lda, w + j, ldw, c + r * ldc + j, depth);
    }
  }
#endif
  scalar_columns(a, lda, w, ldw, c, ldc, rows, depth, j, cols);
}

}  // namespace deixis::nn
