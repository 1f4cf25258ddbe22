#include "net/key_derivation.h"

#include <utility>

namespace deixis::net {

KeyDerivation::~KeyDerivation() {
  join();
}

void KeyDerivation::join() {
  if (thread_.joinable()) {
    thread_.join();
  }
}

void KeyDerivation::start(std::string_view passphrase, const Salt& salt, const KdfCost& cost,
                          bool on_this_thread) {
  join();
  salt_ = salt;
  cost_ = cost;
  job_ = std::make_shared<Job>();
  job_->passphrase.assign(passphrase);
  job_->salt = salt;
  job_->cost = cost;
  const auto work = [](Job& job) {
    job.key = derive_master_key(job.passphrase, job.salt, job.cost);
    wipe(std::as_writable_bytes(std::span(job.passphrase.data(), job.passphrase.size())));
    job.done.store(true, std::memory_order_release);
  };
  if (on_this_thread) {
    work(*job_);
    return;
  }
  // The thread holds its own reference: the job outlives a take() or another start().
  thread_ = std::thread([job = job_, work] { work(*job); });
}

std::optional<Key> KeyDerivation::take() {
  if (!ready()) {
    return std::nullopt;
  }
  join();
  std::optional<Key> key = std::move(job_->key);
  if (job_->key) {
    wipe(*job_->key);
  }
  job_.reset();
  return key;
}

}  // namespace deixis::net
