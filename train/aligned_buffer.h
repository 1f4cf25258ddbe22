#pragma once
// Float buffers whose first element sits on a 64-byte boundary.
//
// Why: Eigen's vectorised reductions (a row's sum, a dot product) peel scalar iterations until
// the data are aligned, so the order in which they add, and hence the last bit of the result,
// depends on where the buffer happens to start. The direct training steps keep their buffers for
// the whole run; a resumed run allocates them afresh, and must compute the same bits as the run
// it continues. With every buffer on the same boundary, it does.

#include <cstddef>
#include <new>
#include <vector>

namespace deixis::train {

template <typename T>
struct CacheLineAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlignment{64};

  CacheLineAllocator() = default;
  template <typename U>
  explicit CacheLineAllocator(const CacheLineAllocator<U>&) {}

  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlignment)); }
  // The unsized form: clang (without -fsized-deallocation) declares no sized aligned delete.
  void deallocate(T* p, std::size_t) { ::operator delete(p, kAlignment); }

  friend bool operator==(const CacheLineAllocator&, const CacheLineAllocator&) { return true; }
};

using AlignedFloats = std::vector<float, CacheLineAllocator<float>>;

}  // namespace deixis::train
