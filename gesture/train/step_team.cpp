#include "gesture/train/step_team.h"

#include <string>

#include "gesture/error.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace deixis::train {

namespace {

// A few hundred nanoseconds of busy waiting, easy on the sibling hyperthread.
void relax() {
#if defined(__x86_64__) || defined(__i386__)
  for (int i = 0; i < 16; ++i) {
    _mm_pause();
  }
#else
  std::this_thread::yield();
#endif
}

// How long a member spins before it sleeps: a training step's team runs come tens of
// microseconds apart, and waking a sleeping thread costs about as much.
constexpr int kSpins = 4000;

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
  for (int i = 0; i < kSpins && running_.load(std::memory_order_acquire) > 0; ++i) {
    relax();
  }
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
    for (int i = 0; i < kSpins && generation_.load(std::memory_order_acquire) == seen; ++i) {
      relax();
    }
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
