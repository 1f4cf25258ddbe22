#pragma once
// Argon2id off the frame loop (docs/protocol.md §5): deriving the passphrase key takes 0.1–1 s on
// purpose, which a site's frame loop or an OpenXR session must never wait for. start() hands the
// work to a thread of its own; the session polls ready() on its ticks and stays in its handshake
// until the key is there. `on_this_thread` derives at once instead, for simulated-clock tests and
// fuzzing, where results must not depend on how fast a thread runs.

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "net/messages.h"
#include "net/passphrase.h"

namespace deixis::net {

class KeyDerivation {
 public:
  KeyDerivation() = default;
  // Waits for a derivation still running (bounded by its cost: at most about a second).
  ~KeyDerivation();
  KeyDerivation(const KeyDerivation&) = delete;
  KeyDerivation& operator=(const KeyDerivation&) = delete;

  // Starts deriving the key for `salt` and `cost` (waiting first for one still running).
  void start(std::string_view passphrase, const Salt& salt, const KdfCost& cost,
             bool on_this_thread);
  bool started() const { return job_ != nullptr; }
  bool ready() const { return job_ != nullptr && job_->done.load(std::memory_order_acquire); }
  // After ready(): the key (nullopt when Argon2id failed: out of memory); clears the job.
  std::optional<Key> take();
  const Salt& salt() const { return salt_; }
  const KdfCost& cost() const { return cost_; }

 private:
  struct Job {
    std::string passphrase;
    Salt salt{};
    KdfCost cost{};
    std::optional<Key> key;
    std::atomic<bool> done{false};
  };
  void join();

  std::shared_ptr<Job> job_;
  std::thread thread_;
  Salt salt_{};
  KdfCost cost_{0, 0};
};

}  // namespace deixis::net
