#include "train/step_team.h"

#include <chrono>
#include <string>

#include "core/error.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace deixis::train {

namespace {

// How long a member spins before it sleeps: a training step's team runs come a few to tens of
// microseconds apart, and waking a sleeping thread costs about as much; between batches (data,
// checkpoints) and epochs the members sleep.
constexpr std::chrono::microseconds kSpin{50};

// Busy-waits until done() or kSpin has passed; true if done.
template <typename Done>
bool spin_until(Done done) {
  const auto until = std::chrono::steady_clock::now() + kSpin;
  while (!done()) {
    for (int i = 0; i < 8; ++i) {
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();  // easy on a sibling hyperthread
#endif
    }
    if (std::chrono::steady_clock::now() > until) {
      return false;
    }
  }
  return true;
}

}  // namespace

StepTeam::StepTeam(int members) : members_(members) {
  if (members < 1) {
    throw Error("StepTeam: a team needs at least one member, not " + std::to_string(members));
  }
  threads_.reserve(static_cast<std::size_t>(members - 1));
  for (int m = 1; m < members; ++m) {
    threads_.emplace_back([this, m] { work(m); });
  }
}

StepTeam::~StepTeam() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  started_.notify_all();
  for (std::thread& t : threads_) {
    t.join();
  }
}

void StepTeam::run(const std::function<void(int)>& task) {
  if (members_ == 1) {
    task(0);
    return;
  }
  {
    const std::lock_guard lock(mutex_);
    task_ = &task;
    failure_ = nullptr;
    running_.store(members_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
  }
  started_.notify_all();
  std::exception_ptr own;
  try {
    task(0);
  } catch (...) {
    own = std::current_exception();
  }
  spin_until([this] { return running_.load(std::memory_order_acquire) == 0; });
  std::unique_lock lock(mutex_);
  finished_.wait(lock, [this] { return running_.load(std::memory_order_acquire) == 0; });
  task_ = nullptr;
  if (own) {
    std::rethrow_exception(own);
  }
  if (failure_) {
    std::rethrow_exception(failure_);
  }
}

void StepTeam::work(int member) {
  long seen = 0;
  for (;;) {
    spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; });
    const std::function<void(int)>* task = nullptr;
    {
      std::unique_lock lock(mutex_);
      started_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      if (stopping_) {
        return;
      }
      seen = generation_.load(std::memory_order_relaxed);
      task = task_;
    }
    std::exception_ptr failure;
    try {
      (*task)(member);
    } catch (...) {
      failure = std::current_exception();
    }
    bool last = false;
    {
      const std::lock_guard lock(mutex_);
      if (failure && !failure_) {
        failure_ = failure;
      }
      last = running_.fetch_sub(1, std::memory_order_acq_rel) == 1;
    }
    if (last) {
      finished_.notify_one();
    }
  }
}

}  // namespace deixis::train
