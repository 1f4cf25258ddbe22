#pragma once
// A fixed team of threads that runs one task on every member and waits for all of them: the
// direct training steps' data parallelism (deixis-train --threads N). The batch is cut into N
// slices, each member computes its slice's gradients, then each member sums and updates its own
// range of the parameters; two team runs per optimiser step.
//
// Member 0 is the calling thread, so a team of one is a plain call. The others spin for up to
// 50 µs, then sleep on a condition variable, between runs: a training step runs the team twice,
// microseconds apart. An exception thrown by any member is rethrown by run() once every
// member has finished.

#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace deixis::train {

class StepTeam {
 public:
  explicit StepTeam(int members);
  ~StepTeam();
  StepTeam(const StepTeam&) = delete;
  StepTeam& operator=(const StepTeam&) = delete;

  int size() const { return members_; }

  // task(m) for every member m in [0, size()), member 0 on this thread; returns when all are done.
  void run(const std::function<void(int)>& task);

 private:
  void work(int member);

  int members_;
  std::mutex mutex_;
  std::condition_variable started_, finished_;
  const std::function<void(int)>* task_ = nullptr;
  std::atomic<long> generation_{0};  // bumped (under the mutex) to start a run
  std::atomic<int> running_{0};      // members other than 0 still working
  bool stopping_ = false;
  std::exception_ptr failure_;
  std::vector<std::thread> threads_;
};

}  // namespace deixis::train
