// Table II's timing (eval/call_timing.h): what happens before the clock starts stays out of the
// mean, and a fast call is timed over many calls.

#include "eval/call_timing.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace deixis::eval {
namespace {

// A network whose first call loads it (20 ms, as a lazily read file would): the mean over the
// timed calls must not contain that. Before the warm-up, 100 timed calls held it: ≥ 200 µs each.
TEST(CallTiming, ASlowFirstCallIsNotInTheMean) {
  int calls = 0;
  double checksum = 0.0;
  const double us = mean_call_us(
      [&] {
        if (calls++ == 0) {
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return 1.0;
      },
      checksum);
  EXPECT_LT(us, 50.0);
  EXPECT_GT(us, 0.0);
  // Every call was counted into the checksum, and a trivial call ran for the whole 0.1 s.
  EXPECT_EQ(checksum, static_cast<double>(calls));
  EXPECT_GT(calls, 1000);
}

// A call of ≈ 1 ms is measured as ≈ 1 ms: the mean divides by the calls that were timed.
TEST(CallTiming, TheMeanIsPerCall) {
  double checksum = 0.0;
  const double us = mean_call_us(
      [] {
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(1000);
        while (std::chrono::steady_clock::now() < until) {
        }
        return 0.0;
      },
      checksum);
  EXPECT_GE(us, 1000.0);
  EXPECT_LT(us, 100000.0);  // far above any scheduling delay, far below a wrong divisor's 100×
}

}  // namespace
}  // namespace deixis::eval
