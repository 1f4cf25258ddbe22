#include "site/link_health.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace deixis::site {

std::string_view link_state_name(LinkState state) {
  switch (state) {
    case LinkState::kLive:
      return "live";
    case LinkState::kStalled:
      return "stalled";
    case LinkState::kWaiting:
      break;
  }
  return "waiting";
}

LinkWindow::Sample LinkWindow::sample_of(double now, const net::JitterStats& stats) {
  return Sample{now, stats.played, stats.missed, stats.waited_sum};
}

void LinkWindow::reset() {
  count_ = 0;
  next_ = 0;
  latest_ = Sample{};
  started_ = false;
}

void LinkWindow::update(double now, const net::JitterStats& stats) {
  latest_ = sample_of(now, stats);
  const bool due = count_ == 0 || now - ring_[(next_ + kSamples - 1) % kSamples].time >= kInterval;
  if (!started_ || due) {
    started_ = true;
    ring_[next_] = latest_;
    next_ = (next_ + 1) % kSamples;
    count_ = std::min(count_ + 1, kSamples);
  }
}

LinkFigures LinkWindow::figures() const {
  LinkFigures f;
  if (count_ == 0) {
    return f;
  }
  // The oldest sample no older than kWindow (the ring holds kWindow / kInterval + 1 of them, so
  // the oldest kept is at most one interval beyond; skip it then).
  std::size_t oldest = (next_ + kSamples - count_) % kSamples;
  if (count_ > 1 && latest_.time - ring_[oldest].time > kWindow + 1e-9) {
    oldest = (oldest + 1) % kSamples;
  }
  const Sample& from = ring_[oldest];
  const std::uint64_t played = latest_.played - std::min(latest_.played, from.played);
  f.dropped = latest_.missed - std::min(latest_.missed, from.missed);
  f.due = played + f.dropped;
  f.buffer_delay_ms =
      played > 0 ? 1000.0 * (latest_.waited_sum - from.waited_sum) / static_cast<double>(played)
                 : -1.0;
  f.window_s = latest_.time - from.time;
  return f;
}

std::size_t format_link_line(std::string_view site, const LinkFigures& link, std::span<char> out) {
  if (out.empty()) {
    return 0;
  }
  const std::string_view state = link_state_name(link.state);
  char rtt[48] = "rtt ?";
  if (link.round_trip_ms >= 0) {
    std::snprintf(rtt, sizeof rtt, "rtt %lld ms%s", static_cast<long long>(link.round_trip_ms),
                  link.via_relay ? " to relay" : "");
  }
  char buffer[48] = "buffer -";
  if (link.buffer_delay_ms >= 0.0) {
    std::snprintf(buffer, sizeof buffer, "buffer %.0f ms", link.buffer_delay_ms);
  }
  const int n =
      std::snprintf(out.data(), out.size(), "%.*s: %.*s, %s, %s, dropped %llu of %llu in %.0f s",
                    static_cast<int>(std::min<std::size_t>(site.size(), 64)), site.data(),
                    static_cast<int>(state.size()), state.data(), rtt, buffer,
                    static_cast<unsigned long long>(link.dropped),
                    static_cast<unsigned long long>(link.due), std::round(link.window_s));
  return n < 0 ? 0 : std::min(static_cast<std::size_t>(n), out.size() - 1);
}

}  // namespace deixis::site
