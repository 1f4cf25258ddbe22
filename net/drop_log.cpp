#include "net/drop_log.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace deixis::net {

DropLog::DropLog(std::shared_ptr<spdlog::logger> logger) : logger_(std::move(logger)) {}

bool LineBudget::take(double now) {
  if (!started_) {
    started_ = true;
    last_refill_ = now;
  }
  tokens_ = std::min(burst_, tokens_ + std::max(0.0, now - last_refill_) * rate_);
  last_refill_ = std::max(last_refill_, now);
  if (tokens_ < 1.0) {
    ++held_since_line_;
    ++held_total_;
    return false;
  }
  tokens_ -= 1.0;
  last_held_ = held_since_line_;
  held_since_line_ = 0;
  return true;
}

bool DropLog::take_token(double now) {
  if (!started_) {
    started_ = true;
    last_refill_ = now;
  }
  const double elapsed = std::max(0.0, now - last_refill_);
  tokens_ = std::min(kBurst, tokens_ + elapsed * kLinesPerSecond);
  last_refill_ = std::max(last_refill_, now);
  if (tokens_ < 1.0) {
    return false;
  }
  tokens_ -= 1.0;
  return true;
}

void DropLog::drop(double now, std::string_view peer, Channel channel, int type, WireResult why) {
  std::uint64_t& count = counters_.by_reason[static_cast<std::size_t>(why.reason)];
  ++count;
  ++counters_.total;
  if (!take_token(now)) {
    ++suppressed_since_line_;
    ++suppressed_total_;
    return;
  }
  spdlog::logger& log = logger_ ? *logger_ : *spdlog::default_logger_raw();
  const std::string_view type_name =
      type < 0 ? std::string_view("empty") : message_name(static_cast<std::uint8_t>(type));
  log.warn(
      "net: dropped {} packet (type 0x{:02x}) from {} on channel {}: {} at {} ({} so far; {} "
      "similar lines held back)",
      type_name, type < 0 ? 0 : type, peer, static_cast<int>(channel), drop_reason_name(why.reason),
      why.field, count, suppressed_since_line_);
  ++lines_;
  suppressed_since_line_ = 0;
}

}  // namespace deixis::net
