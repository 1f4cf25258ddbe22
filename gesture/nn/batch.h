#pragma once
// What the networks need to run a batch of many people's windows at once (Mpnet::run_batch,
// Ugnet::run_batch with buffers): reusable working memory, and the one product every batched
// layer is made of.
//
// Why batches: one person's UGNet MoE reads 2.25 MB of expert weights for 0.56 M multiply-adds, so
// alone it waits on the cache (docs/results.md, per-tick cost). A batch reads each block of
// weights once for every person in it, which makes the same work compute-bound
// (docs/scaling.md).

#include <array>
#include <cstddef>
#include <span>

#include "gesture/nn/params.h"

namespace deixis::nn {

// Working memory of batched runs: a few buffers that only ever grow. Once a batch of the largest
// size has run (or the networks' reserve_batch() sized them), runs of that size or smaller
// allocate nothing. One BatchBuffers serves one thread.
class BatchBuffers {
 public:
  static constexpr int kSlots = 24;

  // Buffer `slot` with room for at least `count` floats (contents unspecified). Allocates only
  // when `count` exceeds the largest size asked of that slot so far.
  std::span<float> get(int slot, std::size_t count) {
    AlignedFloats& buffer = slots_[static_cast<std::size_t>(slot)];
    if (buffer.size() < count) {
      buffer.resize(count);
    }
    return {buffer.data(), count};
  }

 private:
  std::array<AlignedFloats, kSlots> slots_;
};

// c = a·w for `rows` rows: a is rows × depth (row r at a + r·lda), w is depth × cols (row i at
// w + i·ldw), c is rows × cols (row r at c + r·ldc). Each weight row is read once per block of
// rows, not once per row: this is the whole point of batching. With AVX2 + FMA the block is six
// rows by sixteen columns in registers. Every result is the same chain of multiply-adds over i
// in order, whatever the number of rows and wherever the row sits in the batch, so a person's
// results are bit for bit the same alone (rows = 1, the networks' run()) as in any batch.
//
// Where the CPU has AVX-512 (checked at run time; the build itself targets x86-64-v3), every
// column goes through 512-bit kernels (a group's last vector masked): the same chains of
// multiply-adds, so the same bits, at up to twice the arithmetic per instruction
// (docs/scaling.md, decision 86).
void multiply_rows(const float* a, std::size_t lda, const float* w, std::size_t ldw, float* c,
                   std::size_t ldc, int rows, int depth, int cols) noexcept;

// The kernels multiply_rows chooses between: kBuild is what the build targets (AVX2 + FMA, or
// portable code), kAvx512 adds 512-bit kernels (x86-64 builds with FMA by GCC or Clang, on a CPU
// with AVX-512F; not the sanitizer builds, whose portable kernels round differently). Named for
// tests and benchmarks, which compare them.
enum class ProductKernel { kBuild, kAvx512 };
bool product_kernel_available(ProductKernel kernel) noexcept;
// kAvx512 where available, unless the environment's DEIXIS_PRODUCT_KERNEL is `build` (for
// measuring a CPU without AVX-512 on one with it; read once per process).
ProductKernel best_product_kernel() noexcept;
void multiply_rows(ProductKernel kernel, const float* a, std::size_t lda, const float* w,
                   std::size_t ldw, float* c, std::size_t ldc, int rows, int depth,
                   int cols) noexcept;

// People in lanes: the layout of the GRUs' batches (gru.h, step_lanes), where value j of person
// p sits at v + j·ld + p, so that one vector holds the same value of sixteen people. A batch's
// whole groups of kLaneGroup people run in lanes (people_in_lanes); the rest, fewer than sixteen,
// run as rows: a group filled in part costs as much as a full one, more than its people cost as
// rows (docs/scaling.md).
inline constexpr int kLaneGroup = 16;
constexpr int people_in_lanes(int count) noexcept {
  return count / kLaneGroup * kLaneGroup;
}

// c = w·x (+ bias) with people in lanes: w is rows × depth (row j at w + j·ldw, e.g. a GRU's
// weights as PyTorch stores them), x is depth × lanes (row i at x + i·ldx), c is rows × lanes
// (row j at c + j·ldc); `lanes` is a multiple of kLaneGroup. Every result is the same chain of
// multiply-adds over i in order as multiply_rows computes for that person's row (a fused
// multiply-add does not care which factor is which), so the bits are the same in either layout,
// alone or in any batch, with either kernel. With `bias` (one value per row of c), bias[j] is
// added to the finished chain, one addition, as a caller adding it afterwards would.
//
// Why: the GRUs' products are narrow (27 or 72 outputs, depth 9 to 24), and with people as rows
// multiply_rows spends as much time on its blocks' set-up and masked remainders as on the
// arithmetic; with people in lanes every vector is full and the gates that follow are
// elementwise over whole rows (docs/decisions.md, decision 92).
void multiply_lanes(const float* w, std::size_t ldw, const float* x, std::size_t ldx, float* c,
                    std::size_t ldc, int rows, int depth, int lanes,
                    const float* bias = nullptr) noexcept;
void multiply_lanes(ProductKernel kernel, const float* w, std::size_t ldw, const float* x,
                    std::size_t ldx, float* c, std::size_t ldc, int rows, int depth, int lanes,
                    const float* bias = nullptr) noexcept;

// Row `row` of every window (window p's values from windows + p·window_size + row on, `columns`
// of them) in lanes, one lane a person: value c of person p at x + c·count + p. One step's
// inputs of a GRU over `count` windows (a multiple of kLaneGroup), ready for
// project_inputs_lanes.
void window_row_to_lanes(const float* windows, std::size_t window_size, std::size_t row,
                         int columns, int count, float* x) noexcept;

// The opposite way for one vector per person: v (size × lanes, row j at v + j·lanes) → out
// (count × size, person r's values at out + r·size).
void lanes_to_rows(const float* v, int size, int count, int lanes, float* out) noexcept;

}  // namespace deixis::nn
