#pragma once
// Counts dropped packets per reason and logs them at a limited rate (a token bucket on the
// caller's clock: a burst of kBurst lines, then kLinesPerSecond), naming the peer, the message
// type and the reason with its field. Lines that the limit holds back are counted and reported on
// the next line that is written, so a flood of bad packets costs a few lines a second, not a log
// per packet.

#include <array>
#include <cstdint>
#include <memory>
#include <string_view>

#include "net/protocol.h"

namespace spdlog {
class logger;
}

namespace deixis::net {

struct DropCounters {
  std::array<std::uint64_t, kDropReasonCount> by_reason{};
  std::uint64_t total = 0;

  std::uint64_t operator[](DropReason r) const { return by_reason[static_cast<std::size_t>(r)]; }
};

// A token bucket for log lines on the caller's clock: a burst of `burst` lines, then `per_second`.
// What it holds back is counted, so the next line written can say how many were.
class LineBudget {
 public:
  LineBudget(double burst = 5.0, double per_second = 2.0) : burst_(burst), rate_(per_second) {
    tokens_ = burst;
  }
  bool take(double now);  // true: write the line
  // After take() said true: how many lines were held back before this one.
  std::uint64_t held_back() const { return last_held_; }
  std::uint64_t held_back_total() const { return held_total_; }

 private:
  double burst_;
  double rate_;
  double tokens_;
  double last_refill_ = 0.0;
  bool started_ = false;
  std::uint64_t held_since_line_ = 0;
  std::uint64_t last_held_ = 0;
  std::uint64_t held_total_ = 0;
};

class DropLog {
 public:
  static constexpr double kBurst = 5.0;
  static constexpr double kLinesPerSecond = 2.0;

  // `logger` null: spdlog's default logger.
  explicit DropLog(std::shared_ptr<spdlog::logger> logger = nullptr);

  // Counts the drop and, if the rate allows, logs it. `type` is the packet's first byte (or the
  // inner packet's, for a sealed one that opened); `now` in seconds on the caller's clock.
  void drop(double now, std::string_view peer, Channel channel, int type, WireResult why);

  const DropCounters& counters() const { return counters_; }
  std::uint64_t lines_written() const { return lines_; }
  std::uint64_t lines_suppressed() const { return suppressed_total_; }

 private:
  bool take_token(double now);

  std::shared_ptr<spdlog::logger> logger_;
  DropCounters counters_;
  double tokens_ = kBurst;
  double last_refill_ = 0.0;
  bool started_ = false;
  std::uint64_t lines_ = 0;
  std::uint64_t suppressed_since_line_ = 0;
  std::uint64_t suppressed_total_ = 0;
};

// Packets that are not from a message at all (empty) have no type.
inline constexpr int kNoType = -1;

}  // namespace deixis::net
