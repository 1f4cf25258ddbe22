#pragma once
// The simulator's time (docs/sim.md, decisions 45 and 50): in a fixed-step run (scripted input,
// --fixed-step) every frame is one 30 Hz tick, so a scripted run gives the same result on a slow
// machine; otherwise it is the wall clock. A session with another site runs on the wall clock
// (the other site's, ENet's and the jitter buffer's), so a scripted run that starts one from the
// panel follows the wall clock from then on, carrying on from where its steps had got to.

#include <chrono>
#include <cstdint>

namespace deixis::sim {

class SimTime {
 public:
  static constexpr double kTick = 1.0 / 30.0;  // s: 30 Hz (docs/conventions.md#rates-and-windows)

  explicit SimTime(bool fixed_step) : fixed_(fixed_step) {}

  // The simulator time of the next frame, in seconds.
  double next_frame() {
    last_ = fixed_ ? base_ + static_cast<double>(steps_++) * kTick
                   : base_ + std::chrono::duration<double>(Clock::now() - wall_base_).count();
    return last_;
  }
  bool fixed() const { return fixed_; }

  // From the next frame on, the wall clock, from the last frame's time.
  void follow_wall_clock() {
    if (fixed_) {
      fixed_ = false;
      base_ = last_;
      wall_base_ = Clock::now();
    }
  }

 private:
  using Clock = std::chrono::steady_clock;

  bool fixed_;
  double base_ = 0.0;  // s: the time where the current clock starts counting
  Clock::time_point wall_base_ = Clock::now();
  std::uint64_t steps_ = 0;
  double last_ = 0.0;
};

}  // namespace deixis::sim
