#pragma once
// What the simulator's panel plots (docs/sim.md): the last 10 s of the remote avatar's
// progressions (MPNet's gaze, deictic and idle), the blend weights of head and hand, and the
// per-tick timings, in fixed rings so that recording a tick never allocates.

#include <algorithm>
#include <array>
#include <cstddef>

#include "gesture/translator.h"

namespace deixis::sim {

class Ring {
 public:
  static constexpr std::size_t kLength = 300;  // 10 s at 30 Hz

  void push(float v) {
    values_[next_] = v;
    next_ = (next_ + 1) % kLength;
    count_ = std::min(count_ + 1, kLength);
  }
  // As ImGui::PlotLines reads a ring: the values, how many, and where the oldest is.
  const float* data() const { return values_.data(); }
  int count() const { return static_cast<int>(count_); }
  int offset() const { return count_ < kLength ? 0 : static_cast<int>(next_); }
  float last() const { return count_ == 0 ? 0.0f : values_[(next_ + kLength - 1) % kLength]; }
  // The q-quantile (0 … 1) of what the ring holds; 0 when empty. Sorts a copy on the stack.
  float quantile(float q) const {
    if (count_ == 0) {
      return 0.0f;
    }
    std::array<float, kLength> sorted = values_;
    const auto end = sorted.begin() + static_cast<std::ptrdiff_t>(count_);
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<float>(count_ - 1) + 0.5f);
    std::nth_element(sorted.begin(), sorted.begin() + k, end);
    return sorted[static_cast<std::size_t>(k)];
  }

 private:
  std::array<float, kLength> values_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
};

struct SimHistory {
  std::array<Ring, 3> progression;  // gaze, deictic, idle (nn::Progression's order)
  Ring head_weight;
  Ring hand_weight;
  Ring tick_ms;    // translation + IK of the remote avatar
  Ring render_ms;  // both room views
  Ring frame_ms;   // the whole frame, panel and swap included

  void push_tick(const AvatarFrame& frame, double ms) {
    for (std::size_t k = 0; k < progression.size(); ++k) {
      progression[k].push(frame.progression[k]);
    }
    head_weight.push(frame.head_weight);
    hand_weight.push(frame.hand_weight);
    tick_ms.push(static_cast<float>(ms));
  }
};

}  // namespace deixis::sim
