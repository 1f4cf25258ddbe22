#pragma once
// Table II's inference time: the mean wall time of one network call on this machine.

#include <chrono>

namespace deixis::eval {

// Mean time of one call in microseconds. The caller loads the network before (a file's reading
// must not count as inference); a few calls warm caches first, then calls run in rounds of 100
// until 0.1 s has passed, so a 1-µs MLP is timed over many thousands. `call` returns a number
// that is added to `checksum`, which keeps the calls observable to the optimiser.
template <typename Call>
double mean_call_us(Call&& call, double& checksum) {
  using Clock = std::chrono::steady_clock;
  constexpr int kWarmUp = 10;
  constexpr int kRound = 100;
  constexpr std::chrono::milliseconds kMinimum{100};
  for (int i = 0; i < kWarmUp; ++i) {
    checksum += call();
  }
  long calls = 0;
  const Clock::time_point start = Clock::now();
  Clock::duration elapsed{};
  do {
    for (int i = 0; i < kRound; ++i) {
      checksum += call();
    }
    calls += kRound;
    elapsed = Clock::now() - start;
  } while (elapsed < kMinimum);
  return std::chrono::duration<double, std::micro>(elapsed).count() / static_cast<double>(calls);
}

}  // namespace deixis::eval
