#pragma once
// Visiting order of a large layer's weight panels, alternated from call to call.
//
// Why: UGNet's MoE and MLP weights (2.25 MB each) are a little larger than this machine's 2 MB L2
// cache per core. Read in the same order every tick, each pass evicts exactly the data the next
// pass needs first, so every tick streams all weights from L3. Reading the panels forward on one
// call and backward on the next starts each pass with what the previous pass touched last, which
// is still in L2 (measured: UGNet MoE 58 → 46 µs). The order of panels does not change any
// output's summation (each panel is computed the same way every time), so results are identical
// either way; this is only a hint to the cache.
//
// Panels partition a layer's outputs into fixed blocks of at most 64 (a multiple of 8 dividing
// the output count), small enough that a block's accumulators stay in registers.

#include <atomic>

namespace deixis::nn {

constexpr int panel_width(int outputs) {
  for (int p = 64; p >= 8; p -= 8) {
    if (outputs % p == 0) {
      return p;
    }
  }
  return outputs;
}

class PanelOrder {
 public:
  PanelOrder() = default;
  PanelOrder(const PanelOrder&) = delete;
  PanelOrder& operator=(const PanelOrder&) = delete;

  // True on every other call, from any thread (a relaxed counter: the order is only a hint).
  bool next_is_reversed() const noexcept {
    return (calls_.fetch_add(1, std::memory_order_relaxed) & 1u) != 0;
  }

 private:
  mutable std::atomic<unsigned> calls_{0};
};

}  // namespace deixis::nn
