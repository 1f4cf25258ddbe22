#include "gesture/train/step_team.h"

#include <string>

#include "gesture/error.h"

namespace deixis::train {

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
  }
  started_.notify_all();
  for (std::thread& t : threads_) {
    t.join();
  }
}

void StepTeam::run(const std::function<void(int)>& task) {
  {
    const std::lock_guard lock(mutex_);
    task_ = &task;
    running_ = members_ - 1;
    failure_ = nullptr;
    ++generation_;
  }
  started_.notify_all();
  std::exception_ptr own;
  try {
    task(0);
  } catch (...) {
    own = std::current_exception();
  }
  std::unique_lock lock(mutex_);
  finished_.wait(lock, [this] { return running_ == 0; });
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
    const std::function<void(int)>* task = nullptr;
    {
      std::unique_lock lock(mutex_);
      started_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) {
        return;
      }
      seen = generation_;
      task = task_;
    }
    std::exception_ptr failure;
    try {
      (*task)(member);
    } catch (...) {
      failure = std::current_exception();
    }
    {
      const std::lock_guard lock(mutex_);
      if (failure && !failure_) {
        failure_ = failure;
      }
      --running_;
    }
    finished_.notify_one();
  }
}

}  // namespace deixis::train
