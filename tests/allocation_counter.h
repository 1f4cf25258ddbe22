#pragma once
// Counts heap allocations made by the current thread, to prove that hot paths (network ticks,
// translation, IK, packet handling) allocate nothing. allocation_counter.cpp replaces malloc and
// friends for the whole test executable (glibc lets an executable interpose them), so every
// allocation is seen: operator new, Eigen's aligned_malloc, std::vector... Not built under ASan,
// which interposes malloc itself.

#include <cstddef>

namespace deixis::testing {

// Allocations (malloc, calloc, realloc, posix_memalign, aligned_alloc, memalign) by this thread
// since the program started.
std::size_t allocations_on_this_thread();

// Counts allocations made by this thread during its lifetime.
class AllocationCounter {
 public:
  AllocationCounter() : start_(allocations_on_this_thread()) {}
  std::size_t count() const { return allocations_on_this_thread() - start_; }

 private:
  std::size_t start_;
};

}  // namespace deixis::testing
