#pragma once
// Runs independent units of work on a few threads. The evaluation's units (a subject's rows of
// one weight set) share nothing mutable and write their own results, so the caller merges them
// in unit order and the report is the same for any thread count.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace deixis::eval {

// Calls work(i) for every i in [0, count) on up to `threads` threads (at least one), each
// taking the next unrun index. The first exception stops the handing out of new units and is
// rethrown once every thread has finished.
template <typename Work>
void run_units(std::size_t count, int threads, const Work& work) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_lock;
  const auto worker = [&] {
    for (std::size_t i = next++; i < count && !failed; i = next++) {
      try {
        work(i);
      } catch (...) {
        const std::lock_guard<std::mutex> hold(error_lock);
        if (!first_error) {
          first_error = std::current_exception();
        }
        failed = true;
      }
    }
  };
  const auto helpers = static_cast<std::size_t>(std::max(threads, 1)) - 1;
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 0; t < std::min(helpers, count); ++t) {
      pool.emplace_back(worker);
    }
  } catch (const std::system_error&) {
    // No more threads to be had: the ones started and this one do the work.
  }
  worker();  // the calling thread works too
  for (std::thread& t : pool) {
    t.join();
  }
  if (first_error) {
    std::rethrow_exception(first_error);
  }
}

}  // namespace deixis::eval
